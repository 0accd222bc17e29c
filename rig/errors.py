"""The one base of the errors that mean bad input: a record, a vehicle file, an option, a drive or a setting that the
user can mend. Each message names what is wrong and what to do about it; the command line reports any of them in one
line and exits with status 2 (rig/cli/main.py), without importing the modules that raise them."""


class RigError(ValueError):
    """Bad input the user can mend (every user-facing error of the project derives from it)."""
