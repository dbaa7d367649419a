"""What every parameter form is, from the space file to best.patch: the interface of `athrill_sim.tuning.forms`.

A form is one frozen dataclass holding where a parameter's value goes (`define = "KP"` holds the macro). It

- parses its part of a `[[param]]` table (`parse`) and writes it back (`toml`, the journal's header), saying
  what it sets (`sets`: two parameters on one target are refused) and naming its errors, one line each;
- applies a value for a test, through the hooks the tuning (`athrill_sim.tuning`) calls for each binding: the
  compiler flags it builds with (`build_flags`), the source text it rewrites (`source_edit`), the bytes it sets
  in the built image (`image_patch`), the data file it writes (`data_file`);
- writes its part of best.patch (`edits`): the bytes of the user's own files that hold the value.

Every hook has a default that does nothing, so a form overrides only what it does. What a form needs of the
program (`needs`: rebuilding it, its image, a data file) decides which kinds of program it reaches
(`athrill_sim.programs.kinds.kind.ProgramKind.takes`). Adding a form is one module beside these and one line of
`athrill_sim.tuning.bindings.FORMS`.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar, Protocol, TypeVar

from athrill_sim.programs.kinds.kind import ProgramKind
from athrill_sim.programs.program import Program
from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.params import CARRIER, INT_TYPES

T = TypeVar("T")


class BindingError(HakoError, ValueError):
    """A parameter cannot reach the program; the message is one line with the fix."""


@dataclass(frozen=True)
class Edit:
    """Bytes of a user's file to replace, and what they become (one parameter's value, or a whole data
    file from its template)."""

    path: Path
    start: int
    end: int
    text: str
    what: str  # for people: "Kp=1.539 (#define KP)"


@dataclass(frozen=True)
class Form(ABC):
    """One way a parameter's value reaches the program (subclassed as a frozen dataclass of where it goes)."""

    key: ClassVar[str]  # the [[param]] key that names the form: `define = "KP"`
    needs: ClassVar[str | None] = None  # what it needs of the program (REBUILD, IMAGE, DATA_FILE); None: nothing
    table_keys: ClassVar[frozenset[str]] = frozenset()  # the keys of its [[param]] table besides `key`

    # -- the space file -----------------------------------------------------------------------------
    @classmethod
    @abstractmethod
    def parse(cls, name: str, table: Mapping[str, Any]) -> Form:
        """The form of parameter `name` from its [[param]] table; BindingError (one line) if it is not one."""

    @abstractmethod
    def toml(self) -> dict[str, Any]:
        """Its keys as the space file writes them."""

    @abstractmethod
    def describe(self) -> str:
        """Where the value goes, for people: `define KP`."""

    def at(self) -> str:
        """Where the value goes, after a parameter's name in the space's one-line description."""
        return f"({self.describe()})"

    def sets(self, name: str) -> tuple:
        """What parameter `name` sets: two parameters on one target would fight over it."""
        return (self.key, self.describe())

    def conflict(self, name: str, other: str) -> str:
        """The error for parameter `name` on the target of the earlier parameter `other`."""
        return f"{other!r} and {name!r} are two parameters on one target ({self.describe()})"

    @property
    def own_offset(self) -> int | None:
        """The parameter-area offset the program reads the value at; None: the value travels in a slot the
        space allocates, and reaches the program the form's way."""
        return None

    def storage(self, type_: str) -> str:
        """What the value's slot holds, for a parameter of the space's `type_`."""
        return CARRIER

    def check_param(self, name: str, storage: str) -> None:
        """Refuse (BindingError, one line) what the space file alone shows cannot work."""
        return None

    # -- the program, before any test ----------------------------------------------------------------
    def files(self, root: Path) -> list[Path]:
        """The program's files it reads or rewrites besides those its build reads (`root`: the program's
        folder), for the journal's hash and a scratch copy."""
        return []

    def check(self, b: Binding, program: TunedProgram) -> None:
        """Refuse what cannot work (BindingError, one line with the fix), before anything is built."""
        return None

    def check_built(self, b: Binding, program: TunedProgram) -> None:
        """Refuse what cannot work once the program is built with the first values."""
        return None

    # -- a test ---------------------------------------------------------------------------------------
    def build_flags(self, b: Binding, text: str) -> tuple[str, ...]:
        """Compiler flags that build the value in."""
        return ()

    def source_edit(self, b: Binding, text: str, program: TunedProgram) -> tuple[Path, int, int, str] | None:
        """The bytes of a program file that a scratch copy built for this value has instead."""
        return None

    def image_patch(self, b: Binding, value: float, image: Path, program: TunedProgram) -> tuple[int, bytes] | None:
        """(file offset, bytes) to set in a copy of the built image."""
        return None

    def data_file(self, b: Binding, texts: dict[str, str], program: TunedProgram) -> tuple[str, str] | None:
        """(path on the SD card, text) of the data file the test's values make, every parameter's text in
        `texts`."""
        return None

    def shown(self, b: Binding, text: str) -> str:
        """The value as a failed build names it."""
        return f"{b.name}={text}"

    # -- best.patch -----------------------------------------------------------------------------------
    def edits(self, b: Binding, texts: dict[str, str], program: TunedProgram) -> tuple[list[Edit], list[str]]:
        """The edits that give the user's files the value (`texts[b.name]`), and a line for a value no file
        holds."""
        return [], []


@dataclass(frozen=True)
class Binding:
    """One parameter whose value reaches the program by a form other than `offset`, as the physics process is
    told it: the form, and the slot its value comes in."""

    name: str
    form: Form
    slot: int  # RX body offset of the f64 that carries the value
    low: float  # the values it takes: a searched parameter's range, a fixed one's value twice
    high: float
    type: str = "float"  # the space's type: float, int, or a storage type (f32, f64, i8 .. u64)

    @property
    def integer(self) -> bool:
        return self.type == "int" or self.type in INT_TYPES

    @property
    def text_type(self) -> str:
        """The type whose value a text of this parameter stands for: a float parameter's text is read as a
        float32 unless the space says f64."""
        if self.integer:
            return "i64"
        return "f64" if self.type == "f64" else "f32"


class TunedProgram(Protocol):
    """What a form may use of the program it tunes (`athrill_sim.tuning.tune.Tuning`)."""

    @property
    def kind(self) -> ProgramKind: ...
    @property
    def bindings(self) -> tuple[Binding, ...]: ...
    @property
    def root(self) -> Path:
        """The program's folder: where file and source paths start, and where best.patch applies."""
        ...
    @property
    def files(self) -> tuple[Path, ...]:
        """Every file of the program a build or a form reads."""
        ...
    @property
    def lows(self) -> dict[str, float]:
        """Every parameter at its low end: the first values, which the checks build with."""
        ...

    def inside(self, b: Binding, name: str) -> Path:
        """The program's file `name` (relative to `root`); BindingError if it lies outside its folders."""
        ...

    def rel(self, path: Path) -> str:
        """`path` as the user names it, relative to `root`."""
        ...

    def texts(self, values: dict[str, float]) -> dict[str, str]:
        """Every parameter's value as its text."""
        ...

    def built(self, values: dict[str, float]) -> Program:
        """The program built with these values (cached)."""
        ...

    def variant(self, values: dict[str, float]) -> Program:
        """The program as these values make it (built, its image patched)."""
        ...

    def remember(self, key: tuple, make: Callable[[], T]) -> T:
        """`make()`, computed once per key for this program."""
        ...


def file_text(path: Path) -> str:
    """A file of the user's as its bytes are: its line endings kept, and bytes that are not UTF-8 (a Shift-JIS
    comment) kept as they were, so that an edit at an offset in it changes those characters and no others."""
    return path.read_bytes().decode("utf-8", "surrogateescape")


def file_bytes(text: str) -> bytes:
    """What `file_text` read, or an edit of it, as the file's bytes."""
    return text.encode("utf-8", "surrogateescape")


def string_value(key: str, name: str, table: Mapping[str, Any]) -> str:
    """The non-empty string a form's key holds in parameter `name`'s table."""
    value = table[key]
    if not isinstance(value, str) or not value:
        raise BindingError(f"{name!r}: {key} must be a non-empty string")
    return value


@dataclass(frozen=True)
class NamedForm(Form):
    """A form whose key names one thing of the program: `define = "KP"` (a macro), `symbol = "g_kp"` (a
    global)."""

    target: str

    @classmethod
    def parse(cls, name: str, table: Mapping[str, Any]) -> NamedForm:
        return cls(string_value(cls.key, name, table))

    def toml(self) -> dict[str, Any]:
        return {self.key: self.target}

    def describe(self) -> str:
        return f"{self.key} {self.target}"
