"""The one error type of the maze package, so the CLI can turn every bad input into a one-line message, and the exit
statuses mazelog ends with besides click's (1 for an error, 2 for a bad option)."""

EXIT_COMMAND_CAP = 3  # a --mouse run cut at the command cap: its logs are written, but its search never ended
EXIT_INTERRUPTED = 130  # Ctrl-C, as a shell reports a program killed by SIGINT (128 + 2)


class MazeError(Exception):
    """Bad input: a malformed maze file, a corrupt wall log (in strict mode) or an impossible request."""
