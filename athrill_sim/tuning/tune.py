"""A program tuned as it is written: each test's parameter values turned into the program that test runs.

`tune(recipe, bindings)` checks every binding against the program before any test (a missing symbol, a
pattern that matches twice, a template placeholder no parameter fills, a `#define` the program ignores: one
line each, with the fix), and returns the program with its `Tuning`. At each test start the physics process
calls `Tuning.for_test`, which reads the values from their slots and

- writes the data files the forms make onto the test's SD card (a native program's: its working folder);
- picks the variant the rebuilding forms' values make (their compiler flags, their source rewrites), building
  it when it is new (`build_cache`: cached per value, shared by every bench on the machine, so a set that
  repeats builds once);
- sets the image forms' bytes in a copy of that variant's image (`elf_symbols`).

`Tuning.edits` says, for a set of values, which bytes of the user's own files to change so that the program
holds those values with no bench at all: what `best.patch` is made of. What each form does is its own module's
(`athrill_sim.tuning.forms`); this one runs them in order and knows nothing of any one form.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, TypeVar

from athrill_sim.programs.build_cache import CacheKey, cache_root, cached_build, cached_folder
from athrill_sim.programs.kinds.kind import IMAGE, REBUILD, ProgramKind, Recipe
from athrill_sim.programs.program import Program, ProgramError
from athrill_sim.tuning.elf_symbols import patched_copy
from athrill_sim.tuning.forms.form import Binding, BindingError, Edit, file_bytes, file_text
from athrill_sim.tuning.forms.values import value_text
from hakoniwa.wire.params import CARRIER, SLOT_FORMATS
from hakoniwa.wire.protocol import MappedFile

TUNED_IMAGE = "tuned-{key}.elf"  # a v850 image with a test's initial values, in the run directory
T = TypeVar("T")


@dataclass
class Tuning:
    """The bindings of a program, checked against it, and the variants made of it so far (the
    `athrill_sim.tuning.forms.form.TunedProgram` its forms see)."""

    recipe: Recipe
    bindings: tuple[Binding, ...]
    root: Path  # the program's folder: where file and source paths start, and where best.patch applies
    folders: tuple[Path, ...]  # every folder the program's files are in
    files: tuple[Path, ...]  # every file of the program a build or a form reads
    _variants: dict[tuple, Program] = field(default_factory=dict)
    _memo: dict[tuple, Any] = field(default_factory=dict)

    @property
    def kind(self) -> ProgramKind:
        return self.recipe.kind

    @property
    def lows(self) -> dict[str, float]:
        return {b.name: b.low for b in self.bindings}

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
            tmp.write_bytes(file_bytes(text))
            tmp.replace(target)
        return self.variant(values, run_dir)

    def variant(self, values: dict[str, float], run_dir: Path | None = None) -> Program:
        built = self.built({b.name: values[b.name] for b in self.bindings if b.form.needs == REBUILD})
        image = built.image
        patch = dict(p for b in self.bindings if image is not None
                     and (p := b.form.image_patch(b, values[b.name], image, self)) is not None)
        if not patch:
            return built
        if self.kind.image_in_run_dir:  # an image in the run directory, which keeps only the latest
            return built.with_image(self._patched(built, patch, run_dir))
        key = (built.image, tuple(sorted(patch.items())))
        if key not in self._variants:
            self._variants[key] = built.with_image(self._patched(built, patch, run_dir))
        return self._variants[key]

    def data_files(self, values: dict[str, float]) -> dict[str, str]:
        """{path on the SD card: text} of every data file the forms write for `values`."""
        texts = self.texts(values)
        return dict(f for b in self.bindings if (f := b.form.data_file(b, texts, self)) is not None)

    # -- best.patch ---------------------------------------------------------------------------------
    def edits(self, values: dict[str, float]) -> tuple[list[Edit], list[str]]:
        """The edits that give the user's files `values`, and a line for each value no file holds (a define
        that only the command line sets)."""
        edits: list[Edit] = []
        missing: list[str] = []
        texts = self.texts(values)
        for b in self.bindings:
            found, lost = b.form.edits(b, texts, self)
            edits += found
            missing += lost
        return edits, missing

    # -- checks, before any test --------------------------------------------------------------------
    def check(self) -> Program:
        """Refuse what cannot work, with one line each; the program for the bindings' first values."""
        refused = {b.form.key for b in self.bindings if not self.kind.takes(b.form.needs)}
        if refused:
            raise BindingError(self.kind.refusal(refused))
        for b in self.bindings:
            b.form.check(b, self)
        first = self.variant(self.lows)
        for b in self.bindings:
            b.form.check_built(b, self)
        return first

    # -- what the forms use ---------------------------------------------------------------------------
    def inside(self, b: Binding, name: str) -> Path:
        path = (self.root / name).resolve()
        if not any(path == f or f in path.parents for f in self.folders):
            raise BindingError(f"{b.name!r}: {name} is outside the program's folders ({self._rel_list()}); give a "
                               "path inside them, relative to the program's folder")
        return path

    def rel(self, path: Path) -> str:
        return os.path.relpath(path, self.root)

    def texts(self, values: dict[str, float]) -> dict[str, str]:
        return {b.name: value_text(values[b.name], b.text_type) for b in self.bindings}

    def remember(self, key: tuple, make: Callable[[], T]) -> T:
        if key not in self._memo:
            self._memo[key] = make()
        return self._memo[key]

    def built(self, values: dict[str, float]) -> Program:
        """The program built with these values of the rebuilding forms (cached here and on disk)."""
        texts = self.texts({**self.lows, **values})
        rebuilt = [b for b in self.bindings if b.form.needs == REBUILD]
        key = ("build", tuple(texts[b.name] for b in rebuilt))
        if key not in self._variants:
            flags = tuple(f for b in rebuilt for f in b.form.build_flags(b, texts[b.name]))
            if any(b.form.needs == IMAGE for b in self.bindings):
                flags += self.kind.symbol_flags
            edits = [e for b in rebuilt if (e := b.form.source_edit(b, texts[b.name], self)) is not None]
            path = self._rewritten(edits) if edits else self.recipe.path
            try:
                self._variants[key] = self.recipe.make(path, flags)
            except ProgramError as e:
                shown = ", ".join(b.form.shown(b, texts[b.name]) for b in rebuilt)
                raise BindingError(f"the program built with {shown}: {e}") from None
        return self._variants[key]

    # -- the variants ---------------------------------------------------------------------------------
    def _patched(self, built: Program, patch: dict[int, bytes], run_dir: Path | None) -> Path:
        """A copy of the variant's image with the bytes in `patch`: the native Athrill in the cache (the run
        directory may not allow running programs), a v850 image in the run directory."""
        original = built.image
        assert original is not None
        key = CacheKey()
        key.add("image", str(original).encode())
        for offset, raw in sorted(patch.items()):
            key.add(str(offset), raw)
        if not self.kind.image_in_run_dir:
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

    def _rewritten(self, edits: list[tuple[Path, int, int, str]]) -> Path:
        """A scratch copy of the program with each edit made (cached by content): the path of the program in
        it."""
        by_file: dict[Path, list[tuple[int, int, str]]] = {}
        for path, start, end, text in edits:
            by_file.setdefault(path, []).append((start, end, text))
        base = Path(os.path.commonpath([self.root, *self.files]))
        contents = {f: file_bytes(apply_edits(file_text(f), by_file[f])) if f in by_file else f.read_bytes()
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

    def _rel_list(self) -> str:
        return ", ".join(self.rel(f) for f in self.folders)


def tune(recipe: Recipe, bindings: tuple[Binding, ...]) -> Program:
    """The program of `recipe` with `bindings`, checked before any test."""
    path = recipe.path
    root = (path if path.is_dir() else path.parent).resolve() if path is not None else Path.cwd()
    files = recipe.kind.files(path) if path is not None else ()
    extra = [f for b in bindings for f in b.form.files(root)]
    everything = tuple(sorted({*files, *(f.resolve() for f in extra if f.is_file())}))
    folders = tuple(sorted({root, *(f.parent for f in files)}))
    tuning = Tuning(recipe, bindings, root, folders, everything)
    tuning.check()
    base = tuning.built({})
    return replace(base, files=tuple(sorted({*base.files, *everything})), tuning=tuning)


def apply_edits(text: str, edits: Iterable[tuple[int, int, str]]) -> str:
    """`text` with each (start, end, replacement) applied; the spans do not overlap."""
    out, at = [], 0
    for start, end, new in sorted(edits):
        out += [text[at:start], new]
        at = end
    return "".join(out) + text[at:]
