"""The cause registry: one module per cause of the vocabulary in docs/contracts.md, each holding one ``CAUSE``.

Modules in this package are found when it is imported, so a new cause is a new module and nothing else:
vehicle files accept its section, the MJCF builder realises it, the measurement chain applies it, the
diagnosis fits it and the synthetic tests hide it. ``rig/causes/_base.py`` says what a cause provides.

The causes sit above the vehicle: each is registered as an extension of vehicles (rig/vehicle/extensions.py), through
which vehicle files read its section and the MJCF builder realises it without importing this package.
``register_cause`` adds one more (a test's throwaway cause) to both.
"""

from __future__ import annotations

from rig.causes._base import (
    BODY_SHAPES,
    AxleCause,
    CarCause,
    Cause,
    ChannelCause,
    FitParameter,
    ParameterSpec,
    Shape,
    axles_of,
    scale_axle,
    with_extension,
)
from rig.registries import held_by_modules
from rig.vehicle import extensions

#: cause name -> cause, alphabetical
CAUSES: dict[str, Cause] = {}


def register_cause(cause: Cause) -> None:
    """Add ``cause`` to the vocabulary and to the vehicle's extensions (its section, its realisation)."""
    CAUSES[cause.name] = cause
    for name in sorted(CAUSES):
        CAUSES[name] = CAUSES.pop(name)  # alphabetical
    extensions.register(cause)


def unregister_cause(name: str) -> None:
    """Remove the cause called ``name`` (a test's throwaway cause)."""
    CAUSES.pop(name, None)
    extensions.unregister(name)


def _discover() -> None:
    for cause in held_by_modules(__name__, __path__, "CAUSE").values():
        register_cause(cause)


_discover()


def get_cause(name: str) -> Cause:
    """The cause called ``name``; a KeyError that lists the vocabulary otherwise."""
    try:
        return CAUSES[name]
    except KeyError:
        raise KeyError(f"unknown cause '{name}' (known: {', '.join(CAUSES)})") from None


def causes_of(subsystem: str) -> tuple[str, ...]:
    """Names of the causes of one subsystem (``car``, ``rig`` or ``sensor``)."""
    return tuple(name for name, cause in CAUSES.items() if cause.subsystem == subsystem)


def causes_seen_on(test: str) -> tuple[str, ...]:
    """Names of the causes a ``test`` ('rig' or 'track') shows: a wheel's unbalance needs the wheel to roll."""
    return tuple(name for name, cause in CAUSES.items() if cause.seen_on == test)


def damper_line_causes(*parts: str) -> tuple[str, ...]:
    """Names of the causes on a damper's line (``Cause.damper_line``), of the given ``parts`` ('law', 'mount') or
    all: what a dynamometer sees of an axle."""
    return tuple(name for name, cause in CAUSES.items()
                 if cause.damper_line and (not parts or cause.damper_line in parts))


def in_build_order() -> list[Cause]:
    """Causes in the order their realisations are applied to a model."""
    return sorted(CAUSES.values(), key=lambda c: (c.order, c.name))


__all__ = [
    "BODY_SHAPES",
    "CAUSES",
    "AxleCause",
    "CarCause",
    "Cause",
    "ChannelCause",
    "FitParameter",
    "ParameterSpec",
    "Shape",
    "axles_of",
    "causes_of",
    "causes_seen_on",
    "get_cause",
    "in_build_order",
    "register_cause",
    "scale_axle",
    "unregister_cause",
    "with_extension",
]
