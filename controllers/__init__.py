"""Drive-signal tuners and controllers for the rig (RPC iteration, inverse-model drive estimation, policies)."""

from rig.errors import RigError


class ControllerError(RigError):
    """A controller, its parameters or its actuator bounds that cannot be used on this car and road."""


class IterationError(RigError):
    """A drive iteration that cannot run as asked: its settings, or a saved run that resume cannot continue."""
