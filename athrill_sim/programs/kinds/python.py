"""A Python robot program (a built-in name, or `module:function` of an `Ev3Api`) on the mock Athrill,
`athrill-sim`: started one test ahead, and forked by the bench's zygote rather than started afresh."""

from __future__ import annotations

from pathlib import Path

from athrill_sim.programs.kinds.kind import AppSpec, Emulator, ProgramKind, RealEmulator, Recipe
from athrill_sim.programs.program import MOCK_ARGV, Program
from hakoniwa.wire.protocol import SyncMode


class PythonKind(ProgramKind):
    noun = "a Python program"

    def claims(self, app: AppSpec) -> bool:
        from athrill_sim.apps import BUILTIN

        if app.emulator == Emulator.ATHRILL2:
            return False
        if app.spec in BUILTIN:
            return True
        module, _, func = app.spec.partition(":")
        return app.c_source is None and not app.path.is_file() and bool(module and func)

    def recipe(self, app: AppSpec, real: RealEmulator) -> Recipe:
        return Recipe(self, None, lambda _path, _flags: python_program(app.spec))

    def refusal(self, forms: set[str]) -> str:
        return (f"{', '.join(sorted(forms))} parameters reach C programs; a Python program reads its parameters at "
                "their offsets (offset = 540, ...)")


def python_program(spec: str) -> Program:
    mock = (*MOCK_ARGV, "--app", spec)
    return Program(f"python app {spec}", SyncMode.LOCKSTEP, True,
                   (*mock, "--run-dir", "{run_dir}", "--test", "{test}"), check_argv=(*mock, "--check"),
                   files=python_program_files(spec), forkable=True)


def python_program_files(spec: str) -> tuple[Path, ...]:
    """The source files of a Python program: its module and the user's modules it imports."""
    from athrill_sim.apps import BUILTIN
    from athrill_sim.programs.python_sources import program_sources

    return program_sources(BUILTIN.get(spec, spec).partition(":")[0])


PYTHON = PythonKind()
