"""Channel names of the test-record contract (docs/contracts.md): ``<corner>/<quantity>``, SI units."""

CORNERS = ("FL", "FR", "RL", "RR")

#: Quantities of the contract and their SI unit.
QUANTITY_UNITS = {
    "drive": "m",
    "actuator_disp": "m",
    "actuator_force": "N",
    "sprung_acc": "m/s^2",
    "unsprung_acc": "m/s^2",
    "susp_travel": "m",
    "susp_velocity": "m/s",
    "tyre_force": "N",
    "road": "m",
    "control_force": "N",  # force of a suspension controller's actuator (active force or semi-active damper)
    "force": "N",  # damper/force on a dynamometer: positive resisting extension (docs/contracts.md)
    "temperature": "degC",  # damper/temperature: the damper's (oil or body) temperature
    "wheel_angle": "rad",  # unwrapped, 0 at the wheel's mark (an impulse transducer), growing in the rolling direction
}

#: Response quantities a replay returns, in this order per corner.
RESPONSE_QUANTITIES = (
    "sprung_acc",
    "unsprung_acc",
    "susp_travel",
    "susp_velocity",
    "tyre_force",
    "actuator_disp",
    "actuator_force",
)


def channel(corner: str, quantity: str) -> str:
    """The contract name of ``quantity`` at ``corner``, e.g. ``FL/sprung_acc``."""
    return f"{corner}/{quantity}"


def split_channel(name: str) -> tuple[str, str]:
    """``'FL/sprung_acc'`` -> ``('FL', 'sprung_acc')``; ``('', name)`` for a name without a corner."""
    corner, sep, quantity = name.partition("/")
    if not sep:
        return "", name
    return corner, quantity
