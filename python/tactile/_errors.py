"""The exceptions of the package. Their message is the line ``tactile`` prints on the command
line, without its ``tactile: error:`` prefix: it names the file, line and field at fault."""


class TactileError(Exception):
    """Any error of the package."""


class TactileDataError(TactileError, ValueError):
    """Data that breaks its format (a recording, a DataFrame, ``hardware/``) or options out of
    range."""


class TactileFileError(TactileError, OSError):
    """A file that could not be opened, read or written."""
