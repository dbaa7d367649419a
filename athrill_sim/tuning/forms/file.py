"""`file = "sdcard/gains.csv"`: a data file the program reads on its SD card, written for each test from a
template, the file's text with `{Name}` where a parameter's value goes (`template = "..."`, or `template_file`,
a copy of the file with such placeholders). One file takes several parameters, which share its template.
best.patch writes the whole file with the values."""

from __future__ import annotations

import string
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from athrill_sim.programs.kinds.kind import DATA_FILE
from athrill_sim.tuning.forms.form import Binding, BindingError, Edit, Form, TunedProgram, file_text, string_value
from hakoniwa.wire.rundir import SDCARD_DIR


@dataclass(frozen=True)
class File(Form):
    key = "file"
    needs = DATA_FILE
    table_keys = frozenset({"template", "template_file"})

    file: str  # the data file, relative to the program's folder
    template: str | None = None  # its text with {Name} placeholders
    template_file: str | None = None  # a copy of it with placeholders

    @classmethod
    def parse(cls, name: str, table: Mapping[str, Any]) -> File:
        file = string_value(cls.key, name, table)
        template, template_file = table.get("template"), table.get("template_file")
        if not all(v is None or isinstance(v, str) for v in (template, template_file)):
            raise BindingError(f"{name!r}: template and template_file are strings")
        return cls(file, template, template_file)

    def toml(self) -> dict[str, Any]:
        extra = {k: v for k, v in (("template", self.template), ("template_file", self.template_file)) if v is not None}
        return {"file": self.file, **extra}

    def describe(self) -> str:
        return f"file {self.file}"

    def sets(self, name: str) -> tuple:
        return (self.key, name)  # its placeholder: a file takes many parameters

    def check_param(self, name: str, storage: str) -> None:
        if not name.isidentifier():
            raise BindingError(f"{name!r}: a file parameter's name is its {{placeholder}}: use letters, digits and _")

    def files(self, root: Path) -> list[Path]:
        return [root / f for f in (self.file, self.template_file) if f is not None]

    def check(self, b: Binding, program: TunedProgram) -> None:
        program.inside(b, self.file)
        self._template(b, program)

    def data_file(self, b: Binding, texts: dict[str, str], program: TunedProgram) -> tuple[str, str]:
        return self._card(program), fill_template(self._template(b, program), texts)

    def edits(self, b: Binding, texts: dict[str, str], program: TunedProgram) -> tuple[list[Edit], list[str]]:
        """The whole file, once: by the first of its parameters."""
        group = self._group(program)
        if group[0] != b:
            return [], []
        original = program.inside(b, self.file)
        old = file_text(original) if original.is_file() else ""
        return [Edit(original, 0, len(old), fill_template(self._template(b, program), texts),
                     ", ".join(f"{x.name}={texts[x.name]}" for x in group) + " (data file)")], []

    def _card(self, program: TunedProgram) -> str:
        """Where the data file lies on the SD card: relative to the program's sdcard/ folder if it is in it,
        else to the program's folder."""
        root = program.root
        path = (root / self.file).resolve()
        card = root / SDCARD_DIR
        base = card if card in path.parents else root
        return str(path.relative_to(base)) if base in path.parents else path.name

    def _group(self, program: TunedProgram) -> list[Binding]:
        """The parameters of this data file, in the space's order."""
        card = self._card(program)
        return [x for x in program.bindings if isinstance(x.form, File) and x.form._card(program) == card]

    def _template(self, b: Binding, program: TunedProgram) -> str:
        """The data file's template, checked: its parameters give one, every placeholder names one of them,
        every one of them has a placeholder."""
        group = self._group(program)
        first = group[0].form
        assert isinstance(first, File)
        templates = {x.form._given_template(x, program) for x in group
                     if isinstance(x.form, File) and (x.form.template is not None or x.form.template_file is not None)}
        if not templates:
            raise BindingError(f"{group[0].name!r}: file {first.file} needs its template: template = "
                               f'"... {{{group[0].name}}} ..." (the file\'s text, {{Name}} where a value goes), '
                               "or template_file = a copy of the file with such placeholders")
        if len(templates) > 1:
            raise BindingError(f"file {first.file}: its parameters give {len(templates)} different templates; "
                               "give it once")
        template = templates.pop()
        fields = template_fields(template)
        names = {x.name for x in group}
        stray = [f for f in fields if f not in names]
        if stray:
            raise BindingError(f"file {first.file}: template placeholder {{{stray[0]}}} is no parameter of "
                               f"that file (its parameters: {', '.join(sorted(names))}); write a literal brace "
                               "as {{ or }}")
        unused = sorted(names - set(fields))
        if unused:
            raise BindingError(f"{unused[0]!r}: file {first.file}'s template has no {{{unused[0]}}}, so the "
                               "value would reach nothing")
        return template

    def _given_template(self, b: Binding, program: TunedProgram) -> str:
        if self.template is not None and self.template_file is not None:
            raise BindingError(f"{b.name!r}: give template or template_file, not both")
        if self.template is not None:
            return self.template
        path = program.inside(b, self.template_file or "")
        if not path.is_file():
            raise BindingError(f"{b.name!r}: template_file {self.template_file} does not exist in {program.root}")
        return file_text(path)


def template_fields(text: str) -> list[str]:
    """The {Name} placeholders of a template, in order ({{ and }} are literal braces)."""
    fields = []
    try:
        parsed = list(string.Formatter().parse(text))
    except ValueError as e:
        raise BindingError(f"template: {e} (write a literal brace as {{{{ or }}}})") from None
    for _, field, spec, conversion in parsed:
        if field is None:
            continue
        if not field.isidentifier() or spec or conversion:
            raise BindingError(f"template: placeholder {{{field}{'!' + conversion if conversion else ''}"
                               f"{':' + spec if spec else ''}}} is not a parameter's name in braces, as {{Kp}}")
        fields.append(field)
    return fields


def fill_template(text: str, texts: dict[str, str]) -> str:
    return text.format_map(texts)
