"""A program tuned as it is written: each test's parameter values turned into the program that test runs.

`tune(recipe, bindings)` checks every binding against the program before any test (a missing symbol, a
pattern that matches twice, a template placeholder no parameter fills, a `#define` the program ignores: one
line each, with the fix), and returns the program with its `Tuning`. At each test start the physics process
calls `Tuning.for_test`, which reads the values from their slots and

- writes the `file` kinds' data files onto the test's SD card (a native program's: its working folder);
- picks the variant for the `define` and `source` values, building it when it is new (`build_cache`: cached
  per value, shared by every bench on the machine, so a set that repeats builds once);
- sets the `symbol` kinds' initial values in a copy of that variant's image (`elf_symbols`).

`Tuning.edits` says, for a set of values, which bytes of the user's own files to change so that the program
holds those values with no bench at all: what `best.patch` is made of.
"""

from __future__ import annotations

import os
import re
import shutil
import struct
from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path

from athrill_sim.bindings import Binding, BindingError, fill_template, template_fields, typed_value, value_text
from athrill_sim.build_cache import CacheKey, cache_root, cached_build, cached_folder
from athrill_sim.elf_symbols import Global, find_global, loaded_bytes, patched_copy
from athrill_sim.programs import Program, ProgramError, Recipe
from hakoniwa.wire.params import CARRIER, FLOAT_TYPES, SLOT_FORMATS, int_range
from hakoniwa.wire.protocol import MappedFile
from hakoniwa.wire.rundir import SDCARD_DIR

# A native build whose globals are set keeps what finding them needs: the debug information (types), the
# link-time relocations (what reads them) and zero initial values in .data (which a file can hold; .bss is
# zero-filled at start). None of the three changes the code the compiler makes.
NATIVE_SYMBOL_FLAGS = ("-g", "-Wl,--emit-relocs", "-fno-zero-initialized-in-bss")
IMAGE_SYMBOL_FLAGS = ("-fno-zero-initialized-in-bss",)  # EV3RT builds with -g already
TEXT_SUFFIXES = (".c", ".h", ".cpp", ".hpp", ".cc", ".hh", ".cxx", ".inc", ".cfg")
TUNED_IMAGE = "tuned-{key}.elf"  # a v850 image with a test's initial values, in the run directory
_SUFFIX = {"float": re.compile(r"[0-9.]([fFlL])$"), "int": re.compile(r"[0-9]([uUlL]+)$")}


@dataclass(frozen=True)
class Edit:
    """Bytes of a user's file to replace, and what they become (one parameter's value, or a whole data
    file from its template)."""

    path: Path
    start: int
    end: int
    text: str
    what: str  # for people: "Kp=1.539 (#define KP)"


@dataclass
class Tuning:
    """The bindings of a program, checked against it, and the variants made of it so far."""

    recipe: Recipe
    bindings: tuple[Binding, ...]
    root: Path  # the program's folder: where file and source paths start, and where best.patch applies
    folders: tuple[Path, ...]  # every folder the program's files are in
    files: tuple[Path, ...]  # every file of the program a kind reads or rewrites
    _variants: dict[tuple, Program] = field(default_factory=dict)
    _globals: dict[Path, dict[str, Global]] = field(default_factory=dict)

    # -- each test ----------------------------------------------------------------------------------
    def values(self, unity: MappedFile) -> dict[str, float]:
        """What the controller wrote into the slots for this test."""
        return {b.name: float(unity.read(SLOT_FORMATS[CARRIER], b.slot)) for b in self.bindings}

    def for_test(self, run_dir: Path, card: Path, values: dict[str, float]) -> Program:
        """Write this test's data files onto its SD card `card`, and return the program variant its values
        make."""
        for path, text in self.data_files(values).items():
            target = card / path
            target.parent.mkdir(parents=True, exist_ok=True)
            tmp = target.with_name(target.name + ".tmp")
            tmp.write_text(text, newline="")
            tmp.replace(target)
        return self.variant(values, run_dir)

    def variant(self, values: dict[str, float], run_dir: Path | None = None) -> Program:
        built = self.built({b.name: values[b.name] for b in self.bindings if b.kind in ("define", "source")})
        symbols = [b for b in self.bindings if b.kind == "symbol"]
        if not symbols:
            return built
        assert built.image is not None
        found = self._symbols(built.image)
        patch = {found[b.target].file_offset: _encode(found[b.target].storage, values[b.name]) for b in symbols}
        if self.recipe.kind != "native":  # an image in the run directory, which keeps only the latest
            return built.with_image(self._patched(built, patch, run_dir))
        key = (built.image, tuple(sorted(patch.items())))
        if key not in self._variants:
            self._variants[key] = built.with_image(self._patched(built, patch, run_dir))
        return self._variants[key]

    def data_files(self, values: dict[str, float]) -> dict[str, str]:
        """{path on the SD card: text} of every `file` kind's data file for `values`."""
        return {card: fill_template(template, self._texts(values)) for card, (_, template) in self._templates().items()}

    # -- best.patch ---------------------------------------------------------------------------------
    def edits(self, values: dict[str, float]) -> tuple[list[Edit], list[str]]:
        """The edits that give the user's files `values`, and a line for each value no file holds (a define
        that only the command line sets)."""
        edits: list[Edit] = []
        missing: list[str] = []
        texts = self._texts(values)
        for b in self.bindings:
            what = f"{b.name}={texts[b.name]}"
            if b.kind == "define":
                found = list(self._define_sites(b.target))
                edits += [Edit(p, s, e, _literal(old, texts[b.name], b), f"{what} (#define {b.target})")
                          for p, s, e, old in found]
                if not found:
                    missing.append(f"{what}: no file of the program defines {b.target}; build it with "
                                   f"-D{b.target}={texts[b.name]}")
            elif b.kind == "source":
                path, start, end, old = self._source_site(b)
                edits.append(Edit(path, start, end, _literal(old, texts[b.name], b), f"{what} ({b.match})"))
            elif b.kind == "symbol":
                site = self._initializer(b)
                if site is None:
                    missing.append(f"{what}: the definition of {b.target} (TYPE {b.target} = VALUE;) was not found "
                                   "in the program's files; set it there by hand")
                else:
                    path, start, end, old = site
                    edits.append(Edit(path, start, end, _literal(old, texts[b.name], b), f"{what} (global {b.target})"))
        for card, (original, template) in self._templates().items():
            names = [b.name for b in self.bindings if b.kind == "file" and self._card_path(b) == card]
            old = original.read_text() if original.is_file() else ""
            edits.append(Edit(original, 0, len(old), fill_template(template, texts),
                              ", ".join(f"{n}={texts[n]}" for n in names) + " (data file)"))
        return edits, missing

    # -- checks, before any test --------------------------------------------------------------------
    def check(self) -> Program:
        """Refuse what cannot work, with one line each; the program for the bindings' first values."""
        kinds = {b.kind for b in self.bindings}
        if self.recipe.kind == "python":
            raise BindingError(f"{', '.join(sorted(kinds))} parameters reach C programs; a Python program reads "
                               "its parameters at their offsets (offset = 540, ...)")
        if self.recipe.kind == "elf" and kinds & {"define", "source"}:
            raise BindingError("define and source parameters rebuild the program: give its sources (--app FOLDER "
                               "--emulator athrill2), not a built image")
        for b in self.bindings:
            if b.kind in ("file", "source"):
                self._inside(b, b.target)
            if b.kind == "source":
                self._source_site(b)
        self._check_overlaps()
        self._templates()
        first = self.variant({b.name: b.low for b in self.bindings})
        for b in self.bindings:
            if b.kind == "define":
                self._check_define(b)
        return first

    def _check_define(self, b: Binding) -> None:
        low = {x.name: x.low for x in self.bindings}
        high = {**low, b.name: b.high if b.high != b.low else b.low + 1}
        images = [self.built(v).image for v in (low, high)]
        assert images[0] is not None and images[1] is not None
        if loaded_bytes(images[0]) == loaded_bytes(images[1]):
            texts = [self._texts(v)[b.name] for v in (low, high)]
            raise BindingError(f"define {b.target} has no effect: the program built with {b.target}={texts[0]} and "
                               f"with {b.target}={texts[1]} is the same (does it #define {b.target} without "
                               f"#ifndef {b.target}, or not use it?)")

    def _check_overlaps(self) -> None:
        sites = [(b.name, *self._source_site(b)[:3]) for b in self.bindings if b.kind == "source"]
        for i, (name, path, start, end) in enumerate(sites):
            for other, p, s, e in sites[:i]:
                if p == path and s < end and start < e:
                    raise BindingError(f"{other!r} and {name!r} are two parameters on one target: their matches "
                                       f"overlap in {self._rel(path)}")

    def _inside(self, b: Binding, name: str) -> Path:
        path = (self.root / name).resolve()
        if not any(path == f or f in path.parents for f in self.folders):
            raise BindingError(f"{b.name!r}: {name} is outside the program's folders ({self._rel_list()}); give a "
                               "path inside them, relative to the program's folder")
        return path

    # -- the kinds ----------------------------------------------------------------------------------
    def _texts(self, values: dict[str, float]) -> dict[str, str]:
        return {b.name: value_text(values[b.name], b.text_type) for b in self.bindings}

    def built(self, values: dict[str, float]) -> Program:
        """The program built with these define and source values (cached here and on disk)."""
        texts = self._texts({**{b.name: b.low for b in self.bindings}, **values})
        defines = tuple(f"-D{b.target}={texts[b.name]}" for b in self.bindings if b.kind == "define")
        sources = tuple((b.name, texts[b.name]) for b in self.bindings if b.kind == "source")
        key = ("build", defines, sources)
        if key not in self._variants:
            flags = (*defines, *(self._symbol_flags() if any(b.kind == "symbol" for b in self.bindings) else ()))
            path = self._rewritten(dict(sources)) if sources else self.recipe.path
            try:
                self._variants[key] = self.recipe.make(path, flags)
            except ProgramError as e:
                shown = ", ".join([*(d[2:] for d in defines), *(f"{n}={t}" for n, t in sources)])
                raise BindingError(f"the program built with {shown}: {e}") from None
        return self._variants[key]

    def _symbol_flags(self) -> tuple[str, ...]:
        return {"native": NATIVE_SYMBOL_FLAGS, "image": IMAGE_SYMBOL_FLAGS}.get(self.recipe.kind, ())

    def _symbols(self, image: Path) -> dict[str, Global]:
        """The globals of `image` the bindings name, checked: writable, read by the program, of a type the
        parameter's values fit."""
        if image not in self._globals:
            found = {}
            for b in (x for x in self.bindings if x.kind == "symbol"):
                g = find_global(image, b.target, need_reads=self.recipe.kind == "native")
                found[b.target] = _with_storage(g, b)
            self._globals[image] = found
        return self._globals[image]

    def _patched(self, built: Program, patch: dict[int, bytes], run_dir: Path | None) -> Path:
        """A copy of the variant's image with the initial values in `patch`: the native Athrill in the cache
        (the run directory may not allow running programs), a v850 image in the run directory."""
        original = built.image
        assert original is not None
        key = CacheKey()
        key.add("image", str(original).encode())
        for offset, raw in sorted(patch.items()):
            key.add(str(offset), raw)
        if self.recipe.kind == "native":
            def make(scratch: Path) -> None:
                patched_copy(original, patch, scratch / original.name)
                shutil.copymode(original, scratch / original.name)

            return cached_build(cache_root() / "native-tuned" / key.name(), original.name, make)
        folder = run_dir if run_dir is not None else cache_root() / "v850-tuned"
        folder.mkdir(parents=True, exist_ok=True)
        image = folder / TUNED_IMAGE.format(key=key.name())
        if not image.is_file():
            tmp = image.with_name(image.name + f".{os.getpid()}.tmp")
            patched_copy(original, patch, tmp)
            tmp.replace(image)
        if run_dir is not None:  # the emulator starts with its own test: no other test's image is in use
            for old in folder.glob(TUNED_IMAGE.format(key="*")):
                if old != image:
                    old.unlink(missing_ok=True)
        return image

    def _rewritten(self, texts: dict[str, str]) -> Path:
        """A scratch copy of the program with each source match replaced by its value (cached by content):
        the path of the program in it."""
        edits: dict[Path, list[tuple[int, int, str]]] = {}
        for b in (x for x in self.bindings if x.kind == "source"):
            path, start, end, old = self._source_site(b)
            edits.setdefault(path, []).append((start, end, _literal(old, texts[b.name], b)))
        base = Path(os.path.commonpath([self.root, *self.files]))
        contents = {f: apply_edits(f.read_text(), edits[f]).encode() if f in edits else f.read_bytes()
                    for f in self.files}
        key = CacheKey()
        for f, data in sorted(contents.items()):
            key.add(str(f.relative_to(base)), data)

        def write(scratch: Path) -> None:
            for f, data in contents.items():
                target = scratch / "tree" / f.relative_to(base)
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_bytes(data)

        tree = cached_folder(cache_root() / "tuned-sources" / key.name(),
                             lambda entry: entry / "tree" if (entry / "tree").is_dir() else None, write)
        assert tree is not None and self.recipe.path is not None
        return tree / self.recipe.path.resolve().relative_to(base)

    def _source_site(self, b: Binding) -> tuple[Path, int, int, str]:
        """Where the one group of `b.match` lies in its file: exactly one match, or an error with the lines."""
        path = self._inside(b, b.target)
        if not path.is_file():
            raise BindingError(f"{b.name!r}: source file {b.target} does not exist in {self.root}")
        try:
            pattern = re.compile(b.match or "", re.MULTILINE)
        except re.error as e:
            raise BindingError(f"{b.name!r}: match {b.match!r} is not a regular expression: {e}") from None
        if pattern.groups != 1:
            raise BindingError(f"{b.name!r}: match {b.match!r} must have exactly one group, (...), around the value")
        text = path.read_text()
        found = list(pattern.finditer(text))
        if len(found) != 1:
            lines = "; ".join(f"line {text.count(chr(10), 0, m.start()) + 1}: {_line_at(text, m.start())!r}"
                              for m in found[:5])
            raise BindingError(f"{b.name!r}: match {b.match!r} matches {len(found)} times in {b.target}"
                               + (f" ({lines})" if found else "") + "; it must match exactly once")
        m = found[0]
        return path, m.start(1), m.end(1), m.group(1)

    def _define_sites(self, name: str) -> Iterable[tuple[Path, int, int, str]]:
        """The value of every `#define NAME value` in the program's files, and of -DNAME=value in Makefile.inc."""
        define = re.compile(rf"^[ \t]*#[ \t]*define[ \t]+{re.escape(name)}[ \t]+(.*?)[ \t]*(?://.*|/\*.*)?$",
                            re.MULTILINE)
        flag = re.compile(rf"-D{re.escape(name)}=(\S+)")
        for f in self.files:
            pattern = flag if f.name == "Makefile.inc" else define if f.suffix in TEXT_SUFFIXES else None
            if pattern is not None:
                text = f.read_text(errors="replace")
                for m in pattern.finditer(text):
                    yield f, m.start(1), m.end(1), m.group(1)

    def _initializer(self, b: Binding) -> tuple[Path, int, int, str] | None:
        """Where the global's initial value is written in the program's sources: on its definition's line
        (from the debug information), `NAME = VALUE` or `NAME{VALUE}`."""
        image = self.variant({x.name: x.low for x in self.bindings}).image
        assert image is not None
        g = self._symbols(image)[b.target]
        short = re.escape(b.target.rpartition("::")[2])
        pattern = re.compile(rf"\b{short}\s*(?:\[[^\]]*\]\s*)?(?:=\s*([^;,{{}}]+?)|\{{\s*([^;{{}}]+?)\s*\}})\s*[;,]")
        candidates = [f for f in self.files if f.name == g.decl_file] if g.decl_file else []
        for f in candidates:
            text = f.read_text(errors="replace")
            lines = text.split("\n")
            if g.decl_line is None or g.decl_line > len(lines):
                continue
            start = sum(len(line) + 1 for line in lines[:g.decl_line - 1])
            m = pattern.search(text, start)
            if m is not None and text.count("\n", start, m.start()) <= 2:
                group = 1 if m.group(1) is not None else 2
                return f, m.start(group), m.end(group), m.group(group)
        return None

    def _templates(self) -> dict[str, tuple[Path, str]]:
        """{path on the SD card: (the user's data file, its template)}, checked: every placeholder names a
        parameter of that file, every such parameter has a placeholder."""
        by_card: dict[str, list[Binding]] = {}
        for b in (x for x in self.bindings if x.kind == "file"):
            by_card.setdefault(self._card_path(b), []).append(b)
        out = {}
        for card, group in by_card.items():
            original = self._inside(group[0], group[0].target)
            templates = {self._template(b) for b in group if b.template is not None or b.template_file is not None}
            if not templates:
                raise BindingError(f"{group[0].name!r}: file {group[0].target} needs its template: template = "
                                   f'"... {{{group[0].name}}} ..." (the file\'s text, {{Name}} where a value goes), '
                                   "or template_file = a copy of the file with such placeholders")
            if len(templates) > 1:
                raise BindingError(f"file {group[0].target}: its parameters give {len(templates)} different templates; "
                                   "give it once")
            template = templates.pop()
            fields = template_fields(template)
            names = {b.name for b in group}
            stray = [f for f in fields if f not in names]
            if stray:
                raise BindingError(f"file {group[0].target}: template placeholder {{{stray[0]}}} is no parameter of "
                                   f"that file (its parameters: {', '.join(sorted(names))}); write a literal brace "
                                   "as {{ or }}")
            unused = sorted(names - set(fields))
            if unused:
                raise BindingError(f"{unused[0]!r}: file {group[0].target}'s template has no {{{unused[0]}}}, so the "
                                   "value would reach nothing")
            out[card] = (original, template)
        return out

    def _template(self, b: Binding) -> str:
        if b.template is not None and b.template_file is not None:
            raise BindingError(f"{b.name!r}: give template or template_file, not both")
        if b.template is not None:
            return b.template
        path = self._inside(b, b.template_file or "")
        if not path.is_file():
            raise BindingError(f"{b.name!r}: template_file {b.template_file} does not exist in {self.root}")
        return path.read_text()

    def _card_path(self, b: Binding) -> str:
        """Where the data file lies on the SD card: relative to the program's sdcard/ folder if it is in it,
        else to the program's folder."""
        path = (self.root / b.target).resolve()
        card = self.root / SDCARD_DIR
        base = card if card in path.parents else self.root
        return str(path.relative_to(base)) if base in path.parents else path.name

    def _rel(self, path: Path) -> str:
        return os.path.relpath(path, self.root)

    def _rel_list(self) -> str:
        return ", ".join(self._rel(f) for f in self.folders)


def tune(recipe: Recipe, bindings: tuple[Binding, ...]) -> Program:
    """The program of `recipe` with `bindings`, checked before any test."""
    path = recipe.path
    root = (path if path.is_dir() else path.parent).resolve() if path is not None else Path.cwd()
    files = program_files(recipe.kind, path) if path is not None else ()
    extra = [root / x for b in bindings for x in (b.target if b.kind in ("file", "source") else None,
                                                  b.template_file) if x is not None]
    everything = tuple(sorted({*files, *(f.resolve() for f in extra if f.is_file())}))
    folders = tuple(sorted({root, *(f.parent for f in files)}))
    tuning = Tuning(recipe, bindings, root, folders, everything)
    tuning.check()
    base = tuning.built({})
    return replace(base, files=tuple(sorted({*base.files, *everything})), tuning=tuning)


def program_files(kind: str, path: Path) -> tuple[Path, ...]:
    """The files a build of the program at `path` reads (for a scratch copy, and for the journal's hash):
    the native build's and the v850 build's, whichever applies."""
    if kind == "native":
        from athrill_sim.native import NativeBuildError
        from athrill_sim.native.workspace import MAKEFILE_INC, find_app

        try:
            app = find_app(path)
        except NativeBuildError as e:
            raise BindingError(str(e)) from None
        make = [app.root / MAKEFILE_INC] if (app.root / MAKEFILE_INC).is_file() else []
        return tuple(sorted({*app.hashed, *make, *app.sources}))
    if kind == "image":
        from athrill_sim.v850 import ImageError
        from athrill_sim.v850.build import app_files

        try:
            return tuple(app_files(path)[1])
        except ImageError as e:
            raise BindingError(str(e)) from None
    return (path.resolve(),)


def apply_edits(text: str, edits: Iterable[tuple[int, int, str]]) -> str:
    """`text` with each (start, end, replacement) applied; the spans do not overlap."""
    out, at = [], 0
    for start, end, new in sorted(edits):
        out += [text[at:start], new]
        at = end
    return "".join(out) + text[at:]


def _with_storage(g: Global, b: Binding) -> Global:
    """The global with the storage type the parameter is written as: its debug information's, which a type
    in the space must agree with, or the space's where the image has none."""
    given = b.type if b.type not in ("float", "int") else None
    storage = g.storage or given
    if storage is None:
        raise BindingError(f"symbol {b.target}: the image has no debug information to say its type; give it: "
                           'type = "f32" (float), "f64" (double), "i32" (int), ...')
    if given is not None and given != storage:
        raise BindingError(f"symbol {b.target} is {storage} in the program, but the space says type = {given!r}")
    if storage in FLOAT_TYPES and b.integer:
        raise BindingError(f"symbol {b.target} is a {storage} float, but {b.name!r} is an integer parameter: "
                           'drop type = "int"')
    if storage not in FLOAT_TYPES:
        if not b.integer:
            raise BindingError(f"symbol {b.target} is an integer ({storage}): make {b.name!r} an integer "
                               'parameter (type = "int")')
        lo, hi = int_range(storage)
        if not (lo <= b.low and b.high <= hi):
            raise BindingError(f"{b.name!r}: {b.low:g}..{b.high:g} does not fit symbol {b.target} ({storage}: "
                               f"{lo}..{hi})")
    if g.size and g.size != struct.calcsize(SLOT_FORMATS[storage]):
        raise BindingError(f"symbol {b.target} is {g.size} bytes, not one {storage}: tune a scalar global")
    return replace(g, storage=storage)


def _encode(storage: str | None, value: float) -> bytes:
    assert storage is not None
    return struct.pack("<" + SLOT_FORMATS[storage], typed_value(value, storage))


def _literal(old: str, text: str, b: Binding) -> str:
    """The value as a literal in place of `old`, keeping `old`'s C suffix (1.0f stays a float literal)."""
    m = _SUFFIX["int" if b.integer else "float"].search(old.strip())
    return text + m.group(1) if m is not None else text


def _line_at(text: str, offset: int) -> str:
    start = text.rfind("\n", 0, offset) + 1
    end = text.find("\n", offset)
    return text[start:end if end >= 0 else len(text)].strip()
