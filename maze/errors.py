"""The error base of mazelog, so that its CLI turns every error into a one-line message in one place
(`maze.cli.MazeGroup`); its exit statuses are `hakoniwa.wire.exits`'s, the bench's."""


class MazelogError(Exception):
    """What mazelog reports to its user and stops for; `str()` is one line."""


class MazeError(MazelogError):
    """Bad input: a malformed maze file, a corrupt wall log (in strict mode) or an impossible request."""
