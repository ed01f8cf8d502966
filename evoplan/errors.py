"""The errors a user can act on; the CLI prints them as one line and exits with code 2."""


class EvoplanError(Exception):
    """Base class: the message names what is wrong and where (key, value, file)."""


class ConfigError(EvoplanError):
    """A configuration file is missing, unreadable, or holds a bad key or value."""
