"""The one error type of the maze package, so the CLI can turn every bad input into a one-line message."""


class MazeError(Exception):
    """Bad input: a malformed maze file, a corrupt wall log (in strict mode) or an impossible request."""
