"""Drive-signal tuners and controllers for the rig (RPC iteration, inverse-model drive estimation, policies)."""


class ControllerError(ValueError):
    """A controller, its parameters or its actuator bounds that cannot be used on this car and road."""
