"""Forms a category's assets take by size, where the form changes how the object stands.

A counter deeper and wider than :data:`SHAPED_COUNTER_M` is built as an L or a C of
cabinet runs (:func:`~pair2scene.assets.generators.storage.counter_top`), and such
counters stand against walls, in corners, as straight runs do not: of the training
kitchens' floor counters (AI2-THOR + ProcTHOR-1k train), 91 of 94 shaped ones stood
against a wall (1 of them sideways, 77 in a corner) against 120 of 140 straight runs (22
sideways). The hierarchy statistics count the walls of a form apart
(:func:`form_key`), and the wall rules draw a shaped counter's from them.
"""

from __future__ import annotations

from collections.abc import Sequence

SHAPED_COUNTER_M = 1.1
"""A counter deeper and wider than this is an L or a C of cabinet runs, not a block: the
ProcTHOR-1k kitchens' straight runs are 0.61 m deep and their islands 0.92 m, their L and
C counters 1.22 to 3.05 m (62 L, 26 C of 146 counters in the train kitchens)."""
SHAPED = "shaped"
"""The form of an L or C counter."""
FORM_MARK = "#"
"""Joins a category and a form in a statistics key (``counter_top#shaped``)."""


SHOWER_THIN_M = 0.3
"""A shower box thinner than this in x or y is a door or a glass panel, not a cubicle."""


def closed_by_walls(category: str, size: Sequence[float]) -> bool:
    """Whether ``category``'s asset of box ``size`` is built to stand in a corner, the
    room's walls closing it: a shower cubicle
    (:func:`~pair2scene.assets.generators.fixtures.shower`) has a tray, glass or a curtain
    on its front (+y) and right (+x) and nothing at its back (-y, where its head hangs on
    its riser) and its left (-x). Placement stands it with its back to a wall and its
    left to the next (:attr:`~pair2scene.assembly.place.AssemblyConfig.closed_by_walls`):
    mid-room it was an open tray under a pipe. Both training cubicles (AI2-THOR
    FloorPlan412 and 418, 1.10 x 2.21 and 1.22 x 2.32 m) stand so."""
    return category == "shower" and min(float(size[0]), float(size[1])) >= SHOWER_THIN_M


def end_to_wall(category: str, size: Sequence[float]) -> bool:
    """Whether ``category``'s asset of box ``size`` is a panel that stands with an end,
    not a face, at a wall: a shower's glass door or curtain, thinner than
    :data:`SHOWER_THIN_M` (:func:`~pair2scene.assets.generators.fixtures.shower` builds it
    along its longer side), closing a shower off from the room. Of the 18 such panels
    standing on the floor of AI2-THOR's bathrooms, 16 stand across a wall, an end within
    0.31 m of it (FloorPlan403 and 417 the two others); none lies flat along one. The
    training rooms store them unturned (yaw 0, in world axes), so their learned wall
    shares count an end as a back or a side at random: placement puts the end to the
    wall itself (:attr:`~pair2scene.assembly.place.AssemblyConfig.end_to_wall`)."""
    return category == "shower" and not closed_by_walls(category, size)


def form_of(category: str, size: Sequence[float]) -> str | None:
    """The form of ``category``'s asset of box ``size`` (x, y, z metres) that stands
    unlike the category's others, or None."""
    if category == "counter_top" and min(float(size[0]), float(size[1])) >= SHAPED_COUNTER_M:
        return SHAPED
    return None


def form_key(category: str, size: Sequence[float]) -> str | None:
    """The statistics key of ``category``'s form at ``size`` (``counter_top#shaped``), or
    None when the asset takes no particular form."""
    form = form_of(category, size)
    return None if form is None else f"{category}{FORM_MARK}{form}"
