"""The exceptions wildlod raises (shared by the native module and the
pure Python parts)."""


class WildlodError(ValueError):
    """wildlod refused something: a mesh, a file's content, a setting.

    A ``ValueError``, so code that already catches bad values catches it.
    The message names the file, mesh, face, vertex or setting, as the
    command line does.
    """


class WildlodOSError(WildlodError, OSError):
    """The operating system refused a read or write (a missing file,
    permissions, a full disk). Both a :class:`WildlodError` and an
    ``OSError``."""
