"""Sequential placement with rejection sampling: a hierarchy and the layout model -> a scene.

For each tuple of the hierarchy's sequence (every anchor placed before its dependents):

1. the dependent's size is drawn from the training sizes (:class:`SizeTable`) and its
   procedural asset built (seeded by the object id and the scene seed);
2. one forward pass of the layout model gives the mixture; ``batches x candidates`` boxes
   are drawn at once (conditioned on the asset's size) and turned upright (yaw kept);
3. candidates are tried in the order drawn. Each is dropped onto the surface beneath it
   (:func:`rest_on_surfaces`; the floor for floor tuples, whose footprint must lie in the
   room) and rejected when it is carried by nothing, reaches the ceiling, blocks the
   door's swing, or collides: a vectorised oriented-box test against every placed object
   names the possible contacts, and fcl tests the convex parts of those (contact within
   :attr:`Tolerances.touch` is resting, not colliding);
4. the first valid candidate is placed; after ``batches x candidates`` rejections the
   object is dropped with the reason, and so is everything that rests on it.

Before that, every object's asset is drawn (objects on a support at sizes that fit it),
objects beyond :attr:`AssemblyConfig.max_load` of a support's area move to another
support with room (:mod:`pair2scene.assembly.balance`), and each support's dependents are
ordered largest first (:func:`placement_order`). A candidate a little off its surface,
through a wall, in a shallow collision or in a door's swing is nudged (at most
``repair_m`` / ``floor_repair_m``; out of a collision or a door's swing by the shortest
sideways move that clears it, :func:`~pair2scene.assembly.collision.clearing_move`)
instead of rejected; a floor object near a wall is pushed flush.

Two ablations switch steps off (:class:`AssemblyConfig`): ``reject=False`` takes each
object's first candidate untested, ``gravity=False`` keeps its drawn height.

Nothing here can loop: every object costs at most one forward pass and a bounded number
of candidates. Same seed, same model, same hierarchy: the same scene.
"""

from __future__ import annotations

import functools
import math
import time
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, field, replace

import numpy as np

from pair2scene.assembly.anchors import AnchorCheck, AnchorRules, SpotCheck, SpotRules
from pair2scene.assembly.balance import BalanceRules, balance_supports
from pair2scene.assembly.collision import (
    TOLERANCES,
    BoxSet,
    MeshWorld,
    Shape,
    Tolerances,
    clearing_move,
)
from pair2scene.assembly.hanging import draped, hang_clear, hangs_on, hung_size
from pair2scene.assembly.mounting import (
    MAX_COVER,
    MountHeights,
    clear_of_windows,
    covered_share,
    covered_shares,
    crowds,
    dress_window,
    dressing_share,
    fitted_dressing,
    hang_over,
    mount,
    mount_blocked,
    mount_order,
    outlines,
)
from pair2scene.assembly.overlaps import FloorCheck, FloorOverlaps
from pair2scene.assembly.records import Dropped, Moved
from pair2scene.assembly.rest import (
    contact_rectangle,
    dropped,
    footprint,
    into_room,
    on_floor,
    rest_on_surfaces,
)
from pair2scene.assembly.sizes import JITTER, SizeTable, resting_sizes, wider_than_deep
from pair2scene.assembly.walls import (
    CORNER_GAP_M,
    WallRules,
    faced_by,
    free_length,
    free_stretches,
    to_corners,
    turn_sideways,
    wall_order,
    walls_with_room,
    within_reach,
)
from pair2scene.assets.forms import closed_by_walls, end_to_wall, form_of
from pair2scene.assets.identity import asset_seed, library_seed
from pair2scene.assets.mesh import Asset
from pair2scene.assets.surfaces import surfaces_of
from pair2scene.categories import HANGS_OVER, SEATED_AT, SEATS, TURN_FREE, WINDOW_DRESSINGS
from pair2scene.curation.stats import ASKEW_BINS_DEG, split_member
from pair2scene.curation.support import HANGER_CATEGORIES
from pair2scene.errors import UserError, check_ranges
from pair2scene.hierarchy.tree import Hierarchy
from pair2scene.scene.geometry import OrientedBox, matrix_to_yaw, sixd_x_axis, yaw_to_matrix
from pair2scene.scene.model import (
    FLOOR,
    AssetRef,
    Room,
    Scene,
    SceneObject,
    on_wall,
    wall_index,
    wall_support,
)
from pair2scene.scene.navigation import FloorGuard, NavigationConfig
from pair2scene.scene.relations import faces, stands_alone
from pair2scene.scene.relations import footprint as floor_outline
from pair2scene.scene.walls import (
    Wall,
    convex_ends,
    face_contacts,
    wall_contact,
    walls_near,
    walls_of,
)

MAX_CANDIDATES = 100_000
"""Most candidates one object may draw: each is a row of a batched forward pass and a
collision test, so more would be unbounded work, not a better placement."""
MAX_PUSH_ATTEMPTS = 20
"""Most push-outs one candidate may take: two neighbours can push it back and forth for as
long as it is allowed to (10**9 kept one bedroom busy for minutes), and a candidate not
free after a few pushes is better drawn again."""
NO_ROOM = frozenset({"collision", "door", "blocks_path", "outside", "overlap"})
"""Rejections for want of room, which :attr:`AssemblyConfig.dense_give_up` (and
``dense_give_up_support``) counts."""
CORNER_TRIES = 2
"""A corner where this many of an object's candidates did not pass for want of room
(:data:`NO_ROOM`) is not tried again for it: what stands around it does not move while its
candidates are tried, and in a crowded ``beyond`` room (320 objects) trying every
candidate in both corners doubled the time. A candidate that fails for how it was drawn
(``off_wall``: 0.19-0.24 m off its wall; ``side_to_wall``, ``faces_away``) fails as drawn
too and says nothing of the corner. Counted, such misses shut corners early: of the 41
kitchen counters against a wall in 30 fit kitchens, 25 stood in a corner (0.61; the wall
rules draw 0.77), 32 now (0.78)."""
CLOSED_CORNER_TRIES = 16
"""For an object closed by the room's walls (a shower cubicle,
:attr:`AssemblyConfig.closed_by_walls`), candidates slid into its corner that may fail
before it is tried as drawn along its wall instead: until then it is tried in the corner
only."""
ENCLOSURE_M = (0.55, 1.2)
"""How far a shower panel standing across a wall (:attr:`AssemblyConfig.end_to_wall`) is
tried from the corner of its wall (m; drawn uniformly per panel): the shower area it
closes off. AI2-THOR's panels stand 0.53 to 1.23 m from the wall parallel to them (10
measured, median 0.9)."""
ALONG_WALL_M = 0.5
"""A shower panel whose long face comes this close to a wall (parallel to it, within
15 degrees) is rejected (``along_wall``): it closes nothing off."""
PLACEMENT_STREAM = 0x9A1E
"""Second word of the seed of a placement's generator (``[seed, PLACEMENT_STREAM]``):
its draws are a stream of their own, apart from the asset draws seeded by
:func:`~pair2scene.assets.identity.asset_seed` of the same scene seed."""
SPOT_RETRIES = 8
"""Candidates rejected only for standing off their spot on the support that are moved
onto it and tried again when no candidate passed (:attr:`AssemblyConfig.spots`)."""
RESTING_STYLES: dict[str, frozenset[int]] = {
    "toilet_paper": frozenset({0}),
    "television": frozenset({0, 1}),
}
"""The styles a category is built in when it rests on a surface (or the floor), where its
other styles are made for a holder or a wall. A toilet roll stands on its end: lying along
its axis, as on a holder's spindle, with its sheet hanging, it rolled off the cisterns and
counters it was put on (in 30 bathrooms, 9 of 25 rolls moved 3-35 cm in ``evaluate``'s 2 s
simulation). A television stands on its pedestal or two feet: the wall-mounted one, a
panel with a bracket behind it and nothing under it, toppled off its stand (4 of 5 such in
30 living rooms moved 4-15 cm)."""
MOUNTED_STYLES: dict[str, frozenset[int]] = {"television": frozenset({2})}
"""The styles a category is built in when it hangs on a wall: a television on its bracket
(a pedestal or two feet under a panel on a wall was 16 of 21 wall televisions in 60
rooms)."""
STYLE_TRIES = 32
"""Seeds drawn at most for an asset in one of its category's :data:`RESTING_STYLES` or
:data:`MOUNTED_STYLES` (one style of three: about one in 400,000 draws misses it)."""
HALF_RETRIES = 32
"""Candidates rejected only for standing by the other half of their functional anchor
(``wrong_half``) that are tried again, either half taken, when no candidate passed: the
half is a preference the training rooms show, not a reason to leave an object out."""
CROSS_RETRIES = 32
"""Candidates rejected only for lying the other way across their support than drawn
(``crosswise``, :data:`~pair2scene.assembly.anchors.PARALLEL_MIN`) that are tried again,
either way taken, when no candidate passed: a preference, as the half is."""
SEAT_REASONS = ("faces_away", "far_from_anchor")
SEAT_RETRIES = 32
"""Candidates of an object that must face its functional anchor, rejected for facing
away or standing too far from it (``faces_away``, ``far_from_anchor``), that are tried
again seated at it (:func:`seated_at`) when no candidate passed. In 120 fit living rooms
16 chairs found no candidate at their table: at a small round table the model drew every
candidate of the second chair on turned aside or a metre off."""
ASKEW_SALT = 211
"""Salt of the draw of a floor object's turn off the walls' axes (:meth:`Placer._tilt`)."""
ALONE_SALT = 223
"""Salt of the draw of whether a floor object may stand alone in the room
(:meth:`Placer._may_stand_alone`)."""
WALLED_SALT = 227
"""Salt of the size drawn again for an object that, centred on its support, would reach
through a wall (:meth:`Placer._walled_in`)."""
WALLED_JITTER = 1.1
"""How much wider than an observed size :meth:`Placer._walled_in` tests it: two standard
deviations of the jitter a drawn size takes (:data:`~pair2scene.assembly.sizes.JITTER`)."""
LONELY_RETRIES = 32
"""Candidates of a floor object rejected only for standing alone in the room
(``isolated``, :attr:`AssemblyConfig.isolation`) that are tried again, alone allowed,
when no candidate passed: better there than not in the room at all. The same number of
a mid-room object's candidates rejected near a wall (``at_wall``) are tried again by it."""
CROWD_RETRIES = 32
"""Candidates of a mounted object rejected only for hanging close to another on its wall
(``crowded``, :attr:`AssemblyConfig.wall_spacing`) that are tried again, close allowed,
when no candidate passed."""
ACROSS_RETRIES = 32
"""Candidates of a floor object rejected only for facing no wall with room for what the
hierarchy hangs across from it (``no_wall_across``: "a TV on the wall opposite the
sofa", the television's width free of doors and windows) that are tried again without
it when no candidate passed."""
WINDOW_RETRIES = 32
"""Candidates of a mounted object rejected only for covering a window (``window``) that
are tried again slid along their wall beside it (:func:`clear_of_windows`) when no
candidate passed: the model draws a television hung across from its sofa where the sofa
faces, and where a window is there most draws cover it (a 4 x 5 m living room whose sofa
faced its one window: 234 of 256 draws)."""


def _flag(name: str) -> str:
    """The command-line option of an :class:`AssemblyConfig` field."""
    return "--assembly." + name.replace("_", "-")


@dataclass(frozen=True)
class AssemblyConfig:
    """How hard placement tries, and how it draws."""

    candidates: int = 32
    """Candidates drawn per batch (all from the one forward pass)."""
    batches: int = 8
    """Batches before an object is dropped: at most ``candidates x batches`` tries."""
    temperature: float = 0.8
    """Sampling temperature of floor and wall-mounted objects: below 1 favours the model's
    confident modes."""
    support_temperature: float = 1.0
    """Sampling temperature of objects resting on another (a laptop on a dresser, a pillow
    on a sofa). At 0.8 the bundled model's draws kept to their main mode: 13 of 14 laptops
    on bedroom dressers faced the dresser's way where the val rooms' turn a quarter in 5 of
    11 (docs/model.md, "Temperature on supports")."""
    door_clearance_m: float = 0.8
    """Depth in front of (and behind) a door that objects standing in the room must leave
    free, up to the ceiling; at least the door's width (the swing of its leaf). What rests
    on a table by the door must not overhang into it either (a house plant on a dining
    table did, in one of 30 ``beyond`` living rooms)."""
    ceiling_margin_m: float = 0.05
    """Objects must end this far below the ceiling."""
    snap_yaw_deg: float = 45.0
    """A floor object's drawn yaw within this of the walls' axes (every 90 degrees) is
    snapped onto them; 45 snaps every floor object to its nearest wall direction. 83 % of
    the val bedrooms' floor objects stand within 2 degrees of a wall axis, while the
    bundled model's floor yaws are nearly uniform (5 % of raw bed draws within 2 degrees,
    47 % within 20): with a 20-degree snap only 54 % of placed floor objects were aligned
    (`pair2scene evaluate` top views; FID suffered) and resamples were 0.77 vs 0.63.
    The model still picks which wall direction."""
    snap_yaw_support_deg: float = 45.0
    """The same for objects on a support (aligned with the support's axes). 92 % of the
    upright objects on furniture in the AI2-THOR + ProcTHOR-1k train tuples stand within
    2 degrees of their support's axes, while the bundled model's yaws there are broad
    (`benchmarks/support_nats.py`: 3-4 nats per cos / sin dimension behind the per-pair
    Gaussian): with a 10-degree snap only 27 / 28 / 70 % of the placed ones were aligned
    (30 fit bedrooms / living rooms / kitchens), and pose MMD of 100 rooms per type was
    0.100 / 0.122 in bedrooms / living rooms against 0.095 / 0.114 with 45."""
    repair_m: float = 0.25
    """Largest nudge that puts a candidate onto its surface, into the room or out of a
    shallow collision; a farther one is rejected. Measured on 20 fit bedrooms
    (`benchmarks/generate.py`), with ``floor_repair_m`` and ``push_attempts``: 0.15 /
    0.4 m and 2 push-outs gave 0.67 resamples per object, 0.25 / 0.6 m and 5 gave 0.44,
    0.3 / 0.8 m and 8 gave 0.43; mesh collisions stayed 0 (every nudged candidate passes
    the same tests). Push-outs were also capped at the object's own width (a 9 cm card
    12 cm from clear of a lamp's base was rejected): 0.20 -> 0.16 without the cap."""
    floor_repair_m: float = 0.6
    """The same for floor objects (furniture is metres wide: a nudge of a hand's width
    off a wall or a neighbour keeps the model's arrangement)."""
    push_attempts: int = 5
    """Push-outs (of a collision or a door's swing) tried per candidate before it is
    rejected, 0 .. 20 (a push-out can move a candidate into a third object; the next one moves it
    out). Pushing along each contact's own normal, and giving up on a contact from above
    (a remote under a lamp's shade), left 0.34 resamples per object on 20 fit bedrooms;
    the shortest move that clears every contact's footprints at once, 0.20 (both with
    the width cap in ``repair_m``'s note)."""
    wall_snap_m: float = 0.15
    """A floor object standing this close to a wall is pushed flush against it."""
    max_load: float | None = 0.4
    """Share of a support's surface area its dependents may cover before the rest move to
    another support with room (:func:`balance_supports`); None keeps the hierarchy's.
    Measured with the fit hierarchies of the joint statistics (seeds 0-39 bedrooms, 0-19
    kitchens and living rooms): 0.3 gave acceptance 0.985 / 0.84 / 0.99 and mean resamples
    0.14 / 0.71 / 0.12 (a few kitchens' objects, moved off full counters, took many tries
    elsewhere), 0.4 0.99 / 0.87 / 1.00 and 0.13 / 0.18 / 0.13, 0.5 0.99 / 0.88 / 1.00 and
    0.15 / 0.22 / 0.18."""
    dense_max_load: float | None = 0.5
    """The same for ``beyond`` scenes (``place(dense=True)``), which ask for clutter: more
    objects per surface, at the cost of more resamples."""
    dense_give_up: int | None = 96
    """``beyond`` scenes: a floor object with this many candidates rejected for want of
    room (:data:`NO_ROOM`: into a placed object, a door's swing or the path, out of the
    room) tries no more and is dropped (None: all ``candidates x batches``). A room
    filled towards its capacity spent most of its time on furniture that no longer fit:
    at 320 objects asked (bedroom, seed 0), the dressers and side tables that were
    dropped took 28 s of 46 s, each trying all 256 candidates. Candidates rejected for
    other reasons (facing away from their anchor) do not count: such an object may pass
    at its 200th. The rest of its candidates are still drawn, not tried, so that an
    object dropped either way leaves the placement's generator as the full search does: the
    objects after it are drawn the same. Fit scenes try every candidate; objects on
    supports and on walls have their own limit (``dense_give_up_support``)."""
    dense_give_up_support: int | None = 128
    """``dense_give_up`` for objects on a support or a wall: later than a floor object's,
    since a small object finds a gap on a crowded table late (one mug passed after more
    than 96). Of the 2,460 such objects placed in 16 ``beyond`` bedrooms and living
    rooms (160 and 320 objects asked, seeds 0-3) one passed after 32 or more, none after
    96; in the eight of 320 objects, those dropped (most after all 256 candidates) took
    37 s of 230 s."""
    dense_push_attempts: int | None = 2
    """``push_attempts`` for ``beyond`` scenes (None: ``push_attempts``). In a crowded room
    a pushed candidate mostly lands in a third object, and the next push in a fourth: at
    320 objects asked (bedroom, 20 seeds), 5,751 candidates took all five push-outs and
    were rejected, against 164 accepted after a third. With two, the same 20 rooms place
    the same number of objects (6,220; 793 of 40 objects asked) and take 17 % less time
    (median 1.76 -> 1.46 s). Fit scenes keep ``push_attempts``."""
    walls: bool = True
    """Stand floor objects against a wall as often as the training rooms do (per room
    type and category, :class:`~pair2scene.assembly.walls.WallRules`), drawing them in
    the wall's frame (a model with anchor frames), one wall with room for them at a time;
    False draws every floor object in the room's (or its functional anchor's) frame."""
    anchors: bool = True
    """Keep a floor object with a functional anchor at it as the training rooms do
    (:class:`~pair2scene.assembly.anchors.AnchorRules`, per dependent and anchor
    category): facing it as often as they faced theirs (chairs their table), in front of
    it as often (a TV stand in front of the sofa), by the half of it theirs stood by
    (a nightstand by the head of its bed) and no farther from it than they stood;
    candidates that do not are rejected (``faces_away``, ``not_in_front``,
    ``wrong_half``, ``far_from_anchor``) and an object none of whose candidates passes
    is dropped; a wall object with a floor anchor hangs across the room from it as often
    as theirs did (a TV facing the sofa;
    :meth:`~pair2scene.assembly.anchors.AnchorRules.across`), else
    over it. Only for a model that draws in its anchors' frames (``draws_in_frames``; not
    the uniform baseline). False takes whatever candidate the model draws and the other
    tests pass, and tries a wall object's anchor's wall first."""
    spots: bool = True
    """Keep an object on a support where and how the training rooms' did, per dependent
    and support category (:class:`~pair2scene.assembly.anchors.SpotRules`): facing the
    support's way as often as they did where they nearly always did (a television on its
    stand), and no farther from their usual spot on it (a television centred on its
    stand); candidates that do not are rejected (``turned``, ``off_spot``). When every
    candidate is rejected and some only as ``off_spot``, the first of those (up to
    :data:`SPOT_RETRIES`) are moved onto the nearest point of the spot and tried again: a
    television all of whose draws the model puts off-centre stands centred rather than
    nowhere. A pair whose training dependents stood at one spot along an axis (spread
    under :data:`~pair2scene.assembly.anchors.PIN_STD`: a television centred on its stand
    to 1 % of its half width) has each candidate first tried moved onto that spot. Only
    for a model that draws in its anchors' frames, as ``anchors``."""
    mount_heights: bool = True
    """Hang a mounted object (a painting, a mirror, a microwave over the counter) only at
    the heights its category hung at in the training rooms
    (:class:`~pair2scene.assembly.mounting.MountHeights`: the mean +- 2 standard deviations
    + 0.15 m); candidates outside are rejected (``off_height``). The bundled model draws a
    wall microwave anywhere from the floor to the ceiling (10 in the training rooms, at
    1.76 m, spread 0.11 m) and about one painting in twenty above 2.4 m (the highest
    real one: 2.39 m).
    Only for a model that draws in its anchors' frames, as ``anchors``."""
    largest_first: bool = True
    """Place each support's dependents largest footprint first (anchors still first)."""
    confine: bool = True
    """Draw floor objects' candidates only where they can end in the room
    (:func:`floor_region`): the model's distribution restricted there, exactly (what
    rejection leaves of unconfined draws is the same), without drawing the candidates
    that would certainly be rejected as "outside". The bundled model puts about 12 % of a
    floor object's draws (temperature 0.8, 120 fit bedrooms) out of reach; confining them
    took fit bedrooms' resamples per object from 0.21 to 0.16 (seeds 0-39) and from 0.32
    to 0.20 (seeds 100-139). False (``--ablation no-confine``) is plain rejection."""
    tolerances: Tolerances = TOLERANCES
    navigable: bool = True
    """Keep the room navigable (:class:`~pair2scene.scene.navigation.FloorGuard`): a floor
    candidate that cuts reachable floor off from the door, leaves its own front or an
    earlier object's front out of reach, or stands in a door's swing is rejected
    (``blocks_path``). Measured on 60 generated rooms (seeds 0-19 per type): the mean
    reachable share of the free floor went from 0.926 to 0.999 and rooms at 0.97 or more
    from 0.80 to 1.00, at 0.11 -> 0.30 resamples per object in bedrooms."""
    top_free_share: float = 0.02
    """A support's top is kept free (its dependents rest on its shelves or seat) when at
    most this share of its dependents in the training rooms rested on it, of at least 20
    (:meth:`~pair2scene.curation.stats.HierarchyStats.top_kept_free`: fridges, sofas,
    beds); 0 keeps only never-used tops free, a negative value none. Without it 9 of the
    25 things placed in the fridges of 10 kitchens stood on the fridge's roof."""
    navigation: NavigationConfig = NavigationConfig()
    """The agent (radius 0.2 m by default) and the grid the guard keeps the floor for."""
    corners: bool = True
    """A floor object drawn against a wall also stands in a corner of the room, against
    the neighbouring wall too, as often as the training rooms' did (per room type and
    category, :meth:`~pair2scene.assembly.walls.WallRules.corner_rate`: of those against
    a wall, a kitchen's counters 0.68 and fridges 0.76, a bedroom's dressers 0.83): each
    candidate is first tried slid along its wall into its convex corners, the nearer
    first (:func:`~pair2scene.assembly.walls.to_corners`), then as drawn. Needs
    ``walls``."""
    sideways: bool = True
    """A floor object drawn against a wall stands with a side, not its back, against it
    as often as the training rooms' did (per room type and category,
    :meth:`~pair2scene.assembly.walls.WallRules.sideways_rate`: 0.20 of the living-room
    sofas against a wall, their arm to it, facing along it): each candidate is first
    tried turned that way at its place along the wall, facing the room's side of it
    (:func:`~pair2scene.assembly.walls.turn_sideways`), then as drawn; such an object is
    put in no corner. Needs ``walls``."""
    closed_by_walls: bool = True
    """A floor object whose asset is built to be closed by the room's walls (a shower
    cubicle: nothing at its back and left, :func:`~pair2scene.assets.forms.closed_by_walls`)
    always stands with its back to a wall, each candidate first tried slid into the corner
    at its left, then as drawn along the wall. False: the wall rules' draw, as for any
    shower (10 of 12 of the training rooms' against a wall), and 2 of 30 fit bathrooms
    had a cubicle open mid-room."""
    end_to_wall: bool = True
    """A thin shower panel (a glass door or a curtain,
    :func:`~pair2scene.assets.forms.end_to_wall`) always stands across a wall, an end to
    it: its back when its box is thin in x, else turned sideways. False: the wall rules'
    draw, as for any shower, and of the 13 thin panels of 30 fit bathrooms 4 stood
    mid-room and 5 had a long face to a wall."""
    split_hung_over: bool = True
    """A floor object no painting, mirror or wall lamp hangs over stands against a wall,
    in a corner and sideways at the shares of the training rooms' objects of its category
    with none over them (:func:`~pair2scene.curation.stats.under_key`); one with such a
    wall object over it always stands with its back to a wall, in a corner at the share of
    those. False: the category's shares for the first, and the objects a painting hangs
    over are counted twice: the living-room sofas of 120 fit rooms stood with their back to
    a wall 0.79 of the time against the training rooms' 0.65 (p 0.01)."""
    split_wall_rates: bool = True
    """A floor object whose functional anchor stands in the room (a chair at its table)
    stands against a wall, in a corner and sideways at the shares of the training rooms'
    objects of its category that had one, and an object without one (a chair in a room
    with no table) at the shares of those standing alone
    (:meth:`~pair2scene.assembly.walls.WallRules.rate`'s ``anchored``; kitchen chairs 0.21
    and 0.80 against a wall, bedroom chairs 0.15 and 0.75, living-room floor lamps 0.27
    and 0.87). False: one share per category, and a lone chair stood mid-room as often as
    a chair at a table stands away from the walls. Needs ``walls``."""
    split_seats: bool = True
    """A table, desk or dressing table (:data:`~pair2scene.categories.SEATED_AT`) stands
    against a wall, in a corner and sideways at the shares of the training rooms' ones with
    as many seats at them as the hierarchy gives it (up to four,
    :func:`~pair2scene.curation.stats.seats_key`): a dining table with no chair against a
    wall 0.96 of the time, with four or more never. False: the category's shares, and a
    four-chair table drawn into a corner lost chairs that found no room at it. Needs
    ``walls``."""
    seat_at_anchor: bool = True
    """An object that must face its functional anchor
    (:class:`~pair2scene.assembly.anchors.AnchorRules`: a chair at its table) and found no
    candidate is tried again from its candidates rejected for facing away or standing too
    far, each seated at the anchor's nearest side facing it (:data:`SEAT_RETRIES`,
    :func:`seated_at`). False: such an object is dropped."""
    wall_spacing: bool = True
    """A mounted object (not curtains or blinds) keeps at least
    :data:`~pair2scene.curation.stats.CLOSE_WALL_M` along its wall from the others on it,
    unless it draws hanging close (one above another or side by side) with the training
    rooms' share of neighbouring pairs that do
    (:meth:`~pair2scene.assembly.walls.WallRules.keeps_apart`: 0.28); closer candidates
    are rejected (``crowded``) and tried again when none passes. The bundled model drew
    two thirds of the paintings sharing a living-room wall within 0.3 m of each other.
    Needs ``walls``."""
    separate_footprints: bool = True
    """A floor object stands over or under another floor object's footprint (by more than
    :data:`~pair2scene.curation.stats.FLOOR_OVERLAP_SHARE` of the smaller one's) only for
    the category pairs the training rooms show so
    (:class:`~pair2scene.assembly.overlaps.FloorOverlaps`: a chair tucked under its table or
    desk, a plunger by the toilet); other candidates are pushed clear, as out of a
    collision, and else rejected (``overlap``). Mesh collision alone let a side table stand
    under the edge of a dining table's top, a floor lamp's base inside an armchair's
    outline and, in ``beyond`` rooms, oval tables one a few centimetres above another: in
    30 fit rooms a type, 13 / 20 / 4 such pairs in bedrooms / living rooms / kitchens
    against 0 / 3 / 0 in the 38 / 38 / 39 real val rooms. False keeps only the mesh test."""
    asset_library: bool = True
    """Objects take their assets from a finite library, as ProcTHOR's rooms do from its
    asset database: each size the size table observed for a category (1,551 over every
    category) has one mesh (:func:`~pair2scene.assets.identity.library_seed`), and an
    object's size is one of those, unjittered. The same assets come back scene after
    scene, and a process encodes each one's cloud once (the layout model keeps the tokens
    in memory and under the cache folder, :mod:`~pair2scene.model.token_store`; ``pair2scene
    assets tokens`` encodes the whole library once): a warm fit bedroom in 0.18 s instead of
    0.30 s (docs/benchmarks.md). False: each object's
    size is an observed one jittered by :data:`~pair2scene.assembly.sizes.JITTER` and its
    mesh drawn anew, so every asset is new and encoded."""
    matching: bool = True
    """Floor objects of one category in a room are one model (size, style and mesh of the
    first) as often as in the training rooms
    (:meth:`~pair2scene.curation.stats.HierarchyStats.same_model_shares`: a room's chairs
    match in 0.85 of them); False draws each object's model on its own."""
    askew: bool = True
    """Turn floor objects that stand free of the walls off the walls' axes as often and as
    far as the training rooms' did, per category
    (:meth:`~pair2scene.curation.stats.HierarchyStats.askew_shares`: of those standing
    free of the walls, 0.75 of the chairs, most by 5-30 degrees, 0.78 of the floor lamps,
    0.66 of the armchairs, 0.04 of the sofas, no table). Each object draws its turn once
    (seeded by its id), within its bin; its candidates are drawn square (``snap_yaw_deg``)
    and then turned by it. False: every floor object stands square to the walls (0.21 of
    the val bedrooms' floor objects do not)."""
    isolation: bool = True
    """Let a floor object stand alone in the room (further than 0.5 m from every wall and
    every floor object placed before it, :func:`~pair2scene.scene.relations.stands_alone`)
    only as often as its category's objects did in the training rooms
    (:meth:`~pair2scene.curation.stats.HierarchyStats.isolated_shares`: no bed, dresser or
    house plant, 0.02 of the side tables, 0.3 of the coffee tables, 0.6 of the dog beds).
    Each object draws once (seeded by its id) whether it may; if not, its candidates that
    stand alone are rejected (``isolated``) and tried again only when none passed. False:
    wherever the model draws it (a house plant or a side table mid-room)."""
    reject: bool = True
    """Ablation (``--ablation no-rejection``): False takes each object's first candidate
    (after the rest step when ``gravity``; left where drawn when nothing carries it) and
    tests nothing: no room, ceiling, door or collision test, no resamples."""
    gravity: bool = True
    """Ablation (``--ablation no-gravity``): False keeps each candidate's drawn height: no
    drop onto the surface beneath, no nudge onto it, no test that anything carries it. The
    other tests stay; an object sunk into the floor is rejected (reason ``floor``), one sunk
    into its support collides with it."""

    def __post_init__(self) -> None:
        positive = {"candidates": self.candidates, "batches": self.batches,
                    "temperature": self.temperature,
                    "support_temperature": self.support_temperature}  # fmt: skip
        non_negative = {
            "door_clearance_m": self.door_clearance_m, "ceiling_margin_m": self.ceiling_margin_m,
            "snap_yaw_deg": self.snap_yaw_deg, "snap_yaw_support_deg": self.snap_yaw_support_deg,
            "repair_m": self.repair_m, "floor_repair_m": self.floor_repair_m,
            "push_attempts": self.push_attempts, "wall_snap_m": self.wall_snap_m,
        }  # fmt: skip
        loads = {"max_load": self.max_load, "dense_max_load": self.dense_max_load}
        if not np.isfinite(self.top_free_share) or self.top_free_share > 1:
            raise UserError(f"--assembly.top-free-share must be <= 1, got {self.top_free_share}")
        check_ranges("--assembly.", positive, non_negative)
        for name, value in loads.items():
            if value is not None and not (np.isfinite(value) and 0 < value <= 1):
                raise UserError(f"{_flag(name)} must be a share in (0, 1] or none, got {value}")
        for name in ("dense_give_up", "dense_give_up_support"):
            value = getattr(self, name)
            if value is not None and value < 1:
                raise UserError(f"{_flag(name)} must be >= 1 or none, got {value}")
        for name in ("push_attempts", "dense_push_attempts"):
            value = getattr(self, name)
            if value is not None and not 0 <= value <= MAX_PUSH_ATTEMPTS:
                or_none = "" if name == "push_attempts" else " or none"
                raise UserError(f"{_flag(name)} must be in 0 .. {MAX_PUSH_ATTEMPTS}{or_none}, "
                                f"got {value}")  # fmt: skip
        if self.candidates * self.batches > MAX_CANDIDATES:
            raise UserError(
                f"--assembly.candidates x --assembly.batches must be at most {MAX_CANDIDATES}"
                f" (each object draws them all), got {self.candidates * self.batches}"
            )


@dataclass
class AssemblyStats:
    """What placing one scene took."""

    requested: int = 0
    placed: int = 0
    resamples: list[int] = field(default_factory=list)
    """Per placed object: candidates rejected before the accepted one."""
    dropped: list[Dropped] = field(default_factory=list)
    """Per object not placed: why."""
    moved: list[Moved] = field(default_factory=list)
    """Per object moved off a full support before placement: from where to where."""
    repaired: int = 0
    """Accepted candidates that were nudged (onto the surface, into the room, clear of a
    neighbour) rather than taken as drawn."""
    rejections: dict[str, int] = field(default_factory=dict)
    """Rejected candidates by reason: unsupported, outside, wall (on a support, through a
    wall), ceiling, door, collision, blocks_path (would cut the free floor or a front off
    the door)."""
    outside_mass: list[float] = field(default_factory=list)
    """Per floor object: the model's probability of a candidate out of the room's reach
    (:func:`floor_region`), where it no longer draws (``AssemblyConfig.confine``)."""
    seconds: dict[str, float] = field(default_factory=dict)
    """model, assets, collision (rest, broad and narrow phase), total."""

    @property
    def acceptance_rate(self) -> float:
        return self.placed / self.requested if self.requested else 1.0

    @property
    def resamples_per_object(self) -> float:
        return float(np.mean(self.resamples)) if self.resamples else 0.0

    @property
    def mass_outside_room(self) -> float:
        """Mean of :attr:`outside_mass` over the floor objects (0 without any)."""
        return float(np.mean(self.outside_mass)) if self.outside_mass else 0.0

    def to_dict(self) -> dict:
        return {
            "objects_requested": self.requested,
            "objects_placed": self.placed,
            "acceptance_rate": round(self.acceptance_rate, 4),
            "resamples_per_object": round(self.resamples_per_object, 4),
            "moved": [m.to_dict() for m in self.moved],
            "repaired": self.repaired,
            "rejections": dict(sorted(self.rejections.items())),
            "model_mass_outside_room": round(self.mass_outside_room, 4),
            "dropped": [d.to_dict() for d in self.dropped],
            "seconds": {k: round(v, 4) for k, v in self.seconds.items()},
        }


@dataclass
class Placement:
    """A placed scene, what it took, and the assets its objects were placed as (the GLB
    export and physics need the very same meshes)."""

    scene: Scene
    stats: AssemblyStats
    assets: dict[str, Asset]
    """object id -> its asset (local frame; the object's box poses it)."""


@dataclass
class _Placed:
    box: OrientedBox
    asset: Asset


def upright_yaw(x_axis: np.ndarray, reference_yaw: float = 0.0, snap_deg: float = 0.0) -> float:
    """The yaw of a drawn box turned upright about its centre: the heading of its local +x
    axis ``x_axis`` (3,) (0 for an axis straight up or down); a yaw within ``snap_deg`` of
    ``reference_yaw`` + k * 90 degrees is snapped onto it."""
    x, y = x_axis[0], x_axis[1]
    yaw = float(np.arctan2(y, x)) if np.hypot(x, y) > 1e-6 else 0.0
    if snap_deg > 0:
        quarter = np.pi / 2
        k = np.round((yaw - reference_yaw) / quarter)
        snapped = reference_yaw + k * quarter
        if abs(yaw - snapped) <= np.radians(snap_deg):
            yaw = float(snapped)
    return yaw


FACING_REASONS = ("faces_away", "not_in_front", "far_from_anchor", "near_anchor")
"""Why a candidate the hierarchy stands facing its anchor (:attr:`Hierarchy.facing
<pair2scene.hierarchy.tree.Hierarchy.facing>`) was not face to face with it: up to
:data:`SEAT_RETRIES` such are tried again set across from it (:func:`facing_at`) when no
candidate passed. The model draws a sofa at a sofa beside it, as the training rooms' pairs
stood: 7 of 10 second sofas of "two sofas facing each other" found no candidate."""


def facing_at(box: OrientedBox, anchor: OrientedBox) -> OrientedBox:
    """``box`` set in front of ``anchor`` and facing it: along the anchor's front it keeps
    its place (within the anchor's width), and its distance from the anchor's front its
    own, held between :data:`FACING_MIN_GAP_M` and :data:`FACING_GAP_M`."""
    local = anchor.to_local(box.center[None])[0]
    depth = box.half_size[1]
    reach = max(anchor.half_size[0] - box.half_size[0], 0.0)
    gap = np.clip(local[1] - anchor.half_size[1] - depth,  # (a millimetre inside the bounds)
                  FACING_MIN_GAP_M + 1e-3, FACING_GAP_M - 1e-3)  # fmt: skip
    local[0] = np.clip(local[0], -reach, reach)
    local[1] = anchor.half_size[1] + gap + depth
    centre = anchor.to_world(local[None])[0]
    centre[2] = box.center[2]
    return OrientedBox(centre, box.size, yaw_to_matrix(anchor.yaw + np.pi))


def seated_at(box: OrientedBox, anchor: OrientedBox) -> OrientedBox:
    """``box`` moved to the side of ``anchor`` it stands by (the side its centre is
    farthest beyond, in half sizes), its front to that side's edge and facing the anchor
    square, as a chair stands at a table; along the side it keeps its place, its width
    within the side's length where the side is long enough."""
    local = anchor.to_local(box.center[None])[0]
    half = np.maximum(anchor.half_size[:2], 1e-9)
    axis = int(abs(local[1]) / half[1] > abs(local[0]) / half[0])
    side = float(np.sign(local[axis]) or 1.0)
    along = 1 - axis
    reach = max(half[along] - box.half_size[0], 0.0)  # (its whole width by the side)
    local[along] = np.clip(local[along], -reach, reach)
    local[axis] = side * (half[axis] + box.half_size[1])
    centre = anchor.to_world(local[None])[0]
    centre[2] = box.center[2]
    front = -side * anchor.rotation[:2, axis]
    yaw = float(np.arctan2(front[1], front[0])) - np.pi / 2
    return OrientedBox(centre, box.size, yaw_to_matrix(yaw))


def library_assets(sizes: SizeTable, surfaces: bool = False) -> Iterator[Asset]:
    """The asset library's assets (:attr:`AssemblyConfig.asset_library`), as
    :meth:`Placer.assets_for` builds them: each category's observed sizes, standing and
    mounted (from its wall sizes where the table has them, turned wider than deep), and
    each in the style it is placed in too (:func:`placed_style`). What the placer builds
    besides (a towel cut to its rail) is met, and encoded, as generation goes.
    ``surfaces``: work out each asset's support surfaces as it is built, which keeps them
    in the surface store (:mod:`~pair2scene.assets.surface_store`)."""
    from pair2scene.assets.registry import generate

    def built(asset: Asset) -> Asset:
        if surfaces:
            surfaces_of(asset)
        return asset

    for key in sorted(sizes.sizes):
        category, mounted = split_member(key)
        rows = sizes.sizes[key]
        rows = wider_than_deep(rows) if mounted else resting_sizes(category, rows)
        for size in rows:
            asset = generate(category, size, library_seed(category, size))
            yield built(asset)
            placed = placed_style(asset, size, library_seed, mounted)
            if placed is not asset:
                yield built(placed)


def placed_style(asset: Asset, size: np.ndarray, mesh_seed, mounted: bool) -> Asset:
    """``asset``, or one of its category and ``size`` in a style it is built in where it
    is placed (:data:`MOUNTED_STYLES` on a wall, else :data:`RESTING_STYLES`) when its
    category has such styles and ``asset`` is in none of them: built with further seeds,
    ``mesh_seed(category, size, k)`` for k = 1, 2, ... (a seed builds the whole asset, its
    style too, so scene.json's seed rebuilds it exactly; :data:`STYLE_TRIES` at most)."""
    from pair2scene.assets.registry import generate

    want = (MOUNTED_STYLES if mounted else RESTING_STYLES).get(asset.category)
    for k in range(1, STYLE_TRIES + 1):
        if want is None or asset.style in want:
            break
        asset = generate(asset.category, size, mesh_seed(asset.category, size, k))
    return asset


def door_boxes(room: Room, depth: float, height: float) -> list[OrientedBox]:
    """The free space in front of and behind each door: ``depth`` each way, and at least
    the door's width (its leaf's swing, as :mod:`pair2scene.scene.navigation` measures it)."""
    out = []
    for door in room.doors:
        p0, p1 = np.asarray(door.p0, float), np.asarray(door.p1, float)
        along = p1 - p0
        width = float(np.linalg.norm(along))
        if width < 1e-6:
            continue
        yaw = float(np.arctan2(along[1], along[0]))
        mid = (p0 + p1) / 2
        reach = max(depth, width)
        out.append(OrientedBox.from_yaw([*mid, height / 2], [width, 2 * reach, height], yaw))
    return out


def _stack(boxes: list[OrientedBox], margin: float) -> BoxSet:
    if not boxes:
        return BoxSet(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3, 3)), margin)
    return BoxSet(
        np.stack([b.center for b in boxes]),
        np.stack([b.half_size for b in boxes]),
        np.stack([b.rotation for b in boxes]),
        margin,
    )


class Placer:
    """Places hierarchies into rooms with a layout model (see the module docstring)."""

    def __init__(
        self,
        model,
        sizes: SizeTable | None = None,
        config: AssemblyConfig | None = None,
        sup_dep: dict[str, dict[str, int]] | None = None,
        walls: WallRules | None = None,
        anchors: AnchorRules | None = None,
        top_free: frozenset[str] = frozenset(),
        spots: SpotRules | None = None,
        same_model: dict[str, float] | None = None,
        heights: MountHeights | None = None,
        overlaps: FloorOverlaps | None = None,
        askew: dict[str, np.ndarray] | None = None,
        isolated: dict[str, float] | None = None,
    ):
        self.model = model
        self.sizes = SizeTable.load() if sizes is None else sizes
        self.config = config or AssemblyConfig()
        self.sup_dep = sup_dep
        """support category -> dependent category -> count (the hierarchy statistics):
        where :func:`balance_supports` may move objects from a full support."""
        self.walls = walls
        """Which floor objects stand against a wall, and which wall first (None: none
        takes a wall anchor)."""
        self.anchors = anchors
        """How floor objects stand at their functional anchors (None: anywhere the model
        draws them)."""
        self.top_free = top_free
        """Support categories whose box top holds nothing in the training rooms
        (:meth:`~pair2scene.curation.stats.HierarchyStats.top_kept_free`: a fridge's eggs
        are inside it, a sofa's cushions on its seat): their dependents rest on a surface
        below the top."""
        self.spots = spots
        """Where and how objects stand on their supports (None: as the model draws
        them)."""
        self.heights = heights
        """At what heights mounted objects hang (None: where the model draws them)."""
        self.overlaps = overlaps
        """Which floor objects may stand over or under another's footprint
        (:attr:`AssemblyConfig.separate_footprints`; None: any the mesh test lets)."""
        self.same_model = same_model or {}
        """Floor category -> share of training rooms whose objects of it are one model
        (:attr:`AssemblyConfig.matching`)."""
        self.askew = askew or {}
        """Floor category -> shares of its free-standing objects in each bin of turns off
        the walls' axes (:attr:`AssemblyConfig.askew`)."""
        self.isolated = isolated or {}
        """Floor category -> share of its floor objects that stood alone in the room
        (:attr:`AssemblyConfig.isolation`)."""

    def assets_for(
        self, hierarchy: Hierarchy, seed: int, given: dict[str, Asset] | None = None
    ) -> dict[str, Asset]:
        """Every object's asset, seeded by its id and the scene seed (``given`` ones, kept
        objects', as they are). Objects on a support take a size that fits one of its
        surfaces (a book shorter than the shelf's clearance, a television about as wide
        as its stand's top, as the training rooms' were: :attr:`SpotGeometry.overhang
        <pair2scene.assembly.anchors.SpotGeometry.overhang>`) when the data has one. The
        floor objects of a category share its first one's asset in a room drawn to match
        (:attr:`AssemblyConfig.matching`). A table with chairs at it takes a size whose
        edge seats them (:func:`seats_fit`; a table of
        :data:`~pair2scene.categories.SEATED_AT`), and one the hierarchy stands mid-room a
        size of no particular form (:func:`mid_room_fit`: a straight counter)."""
        from pair2scene.assets.registry import generate

        assets: dict[str, Asset] = dict(given or {})
        models: dict[str, Asset | None] = {}  # floor category -> the room's one model of it
        seats = seats_of(hierarchy)
        for item in hierarchy.sequence():
            node = item.dependent
            if node.id in assets:
                continue
            if item.support == FLOOR and self.config.matching:
                if models.get(node.category) is not None:
                    assets[node.id] = models[node.category]
                    continue
            rng = np.random.default_rng(asset_seed(node.id, seed))
            held = assets.get(item.support) if item.support != FLOOR else None
            if held is not None and hangs_on(node.category, held):  # a towel on its rail
                size = hung_size(self.sizes.draw(node.category, rng, self._jitter, fits=draped,
                                                 room_type=hierarchy.room_type), held)  # fmt: skip
                mesh_seed = self._mesh_seeds(rng)
                assets[node.id] = generate(node.category, size, mesh_seed(node.category, size))
                continue
            margins = [None]
            seated = seats[node.id] if node.category in SEATED_AT else 0
            unheld = None  # what a floor object's size must suit, if anything
            if seated > 1:  # (seats stand on the floor with their anchor)
                unheld = seats_fit(seated)
            elif node.id in hierarchy.mid_room:  # an island: a straight run, not an L
                unheld = mid_room_fit(node.category)
            if held is not None:
                overhang = self._overhang(node.category, held)
                margins = [FIT_MARGIN] if overhang is None else [overhang, FIT_MARGIN]
            for k, margin in enumerate(margins):
                fits = unheld if margin is None else surface_fit(held, margin)
                asset = self._draw_asset(node.category, item.support, held, fits, rng,
                                         hierarchy.room_type)  # fmt: skip
                if k + 1 == len(margins) or no_room_on(asset, held) is None:
                    break  # (one drawn wider than its support can carry: as narrow as any)
            assets[node.id] = asset
            if item.support == FLOOR and node.category not in models:
                share = self.same_model.get(node.category, 0.0)
                one = np.random.default_rng(asset_seed(f"{node.category}#model", seed))
                models[node.category] = asset if share > 0 and one.random() < share else None
        return assets

    def _overhang(self, category: str, held: Asset) -> float | None:
        """How far past its support's surface ``category`` may reach on ``held``, where
        the training rooms' pairs reached further than :data:`FIT_MARGIN` (a television
        on its stand: :attr:`SpotGeometry.overhang
        <pair2scene.assembly.anchors.SpotGeometry.overhang>`); None elsewhere."""
        if not (self.config.spots and self.spots is not None):
            return None
        rule = self.spots.rule(category, held.category)
        return rule.overhang if rule is not None and rule.overhang > FIT_MARGIN else None

    @property
    def _jitter(self) -> float:
        """The jitter of a drawn size: none for the asset library, whose assets are the
        observed sizes."""
        return 0.0 if self.config.asset_library else JITTER

    def _mesh_seeds(self, rng: np.random.Generator):
        """How an object's mesh is seeded, ``(category, size, variant=0) -> int``: by its
        category and size for the asset library (:func:`library_seed`), else drawn from
        ``rng``."""
        if self.config.asset_library:
            return library_seed
        return lambda category, size, variant=0: int(rng.integers(2**31))

    def _draw_asset(
        self, category: str, support: str, held: Asset | None, fits,
        rng: np.random.Generator, room_type: str | None,
    ) -> Asset:  # fmt: skip
        """An asset of ``category`` on ``support`` (``held``: its asset, if an object), of a
        size drawn with ``rng`` among those ``fits`` accepts (:meth:`SizeTable.draw
        <pair2scene.assembly.sizes.SizeTable.draw>`), in the style it is placed in."""
        from pair2scene.assets.registry import generate

        mesh_seed = self._mesh_seeds(rng)
        size = self.sizes.draw(category, rng, self._jitter, fits=fits, mounted=on_wall(support),
                               room_type=room_type)  # fmt: skip
        # An integer seed for the mesh, recorded in scene.json: read back, the scene
        # rebuilds exactly these shapes (assembly.keep.keep_assets).
        asset = generate(category, size, mesh_seed(category, size))
        if held is None or held.category not in HANGER_CATEGORIES:
            asset = placed_style(asset, size, mesh_seed, on_wall(support))
        return asset

    def _walled_in(
        self, node, asset: Asset, support: str, sp: _Placed, room: Room, seed: int
    ) -> Asset:
        """``asset``, or one of a size that stays clear of the walls centred on ``sp`` when
        ``asset`` was drawn wider than the support (:meth:`_overhang`) and, centred on it,
        would reach through a wall: a television as wide as its stand overhangs the
        stand's ends, and a stand in a corner has a wall at one end. In 120 fit living
        rooms (seeds 0-119) 8 of 18 televisions dropped so, each after 256 candidates
        rejected as ``wall``. The size is drawn among those that fit the surface as the
        pair's did and, centred and :data:`WALLED_JITTER` wider, clear the walls; the
        asset stays when none does."""
        overhang = self._overhang(node.category, sp.asset)
        if overhang is None or asset.size[0] <= sp.box.size[0]:
            return asset
        if on_floor(OrientedBox(sp.box.center, asset.size, sp.box.rotation), room.floor_polygon):
            return asset
        on_surface = surface_fit(sp.asset, overhang)

        def fits(sizes: np.ndarray) -> np.ndarray:
            clear = [on_floor(OrientedBox(sp.box.center, size * [WALLED_JITTER, 1, 1],
                                          sp.box.rotation), room.floor_polygon)
                     for size in sizes]  # fmt: skip
            return on_surface(sizes) & np.array(clear, bool)

        if not fits(self.sizes.observed(node.category)).any():
            return asset
        rng = np.random.default_rng([asset_seed(node.id, seed), WALLED_SALT])
        return self._draw_asset(node.category, support, sp.asset, fits, rng, None)

    def place(
        self,
        hierarchy: Hierarchy,
        room: Room,
        seed: int = 0,
        scene_id: str = "scene",
        keep: list[SceneObject] | None = None,
        keep_assets: dict[str, Asset] | None = None,
        dense: bool = False,
        assets: dict[str, Asset] | None = None,
    ) -> Placement:
        """Place ``hierarchy`` in ``room``; ``keep`` objects (with their assets) are fixed
        where they are and the hierarchy's objects are placed around and on them.
        ``assets``: what :meth:`assets_for` gave for this hierarchy and seed (drawn here
        when None)."""
        from pair2scene.assets.registry import generate
        from pair2scene.model.api import Anchor, PlacementQuery

        cfg = self.config
        start = time.perf_counter()
        timer = {"model": 0.0, "assets": 0.0, "collision": 0.0}
        generator = np.random.default_rng([seed, PLACEMENT_STREAM])
        kept = {o.id for o in keep or []}
        stats = AssemblyStats(requested=sum(1 for n in hierarchy.nodes if n.id not in kept))
        world = MeshWorld(cfg.tolerances)
        placed: dict[str, _Placed] = {}
        objects: list[SceneObject] = []
        room_walls = {w.index: w for w in walls_of(room.floor_polygon)}
        hung: set[str] = set()  # ids of the placed objects on a wall
        floor_ids: list[str] = []  # those on the floor
        shown: list[tuple[str, OrientedBox, Wall]] = []  # those nothing may cover (not curtains)
        stacked = BoxSet.growing(cfg.tolerances.box_margin)  # the boxes of ``placed``, in order
        for obj in keep or []:
            asset = keep_assets[obj.id]
            shape = Shape(asset)
            shape.set_pose(obj.box.rotation, obj.box.center)
            world.add(obj.id, shape)
            placed[obj.id] = _Placed(obj.box, asset)
            stacked.add(obj.box.center, obj.box.half_size, obj.box.rotation)
            objects.append(obj)
            if obj.support == FLOOR:
                floor_ids.append(obj.id)
            if on_wall(obj.support):
                hung.add(obj.id)
                wall = room_walls.get(wall_index(obj.support))
                if wall is not None and obj.category not in WINDOW_DRESSINGS:
                    shown.append((obj.id, obj.box, wall))
        guard = None
        if cfg.navigable and cfg.reject:
            guard = FloorGuard.for_room(room, config=cfg.navigation)
            for obj in keep or []:
                if obj.support == FLOOR or obj.box.bottom < cfg.navigation.clearance_m:
                    guard.add(obj.box)
        bounds = room.bounds
        door_zones = door_boxes(room, cfg.door_clearance_m, room.height)
        doors = (door_zones, _stack(door_zones, cfg.tolerances.box_margin))
        n = cfg.candidates * cfg.batches
        rejections = stats.rejections
        framed = bool(getattr(self.model, "draws_in_frames", False))
        dressed: set[int] = set()  # windows with curtains or blinds

        t0 = time.perf_counter()
        if assets is None:
            assets = self.assets_for(hierarchy, seed, keep_assets)
        overflow: dict[str, str] = {}
        max_load = cfg.dense_max_load if dense else cfg.max_load
        if max_load is not None and self.sup_dep is not None:
            hierarchy, stats.moved, full = balance_supports(
                hierarchy, assets, self.sup_dep, BalanceRules(max_load), kept
            )
            overflow = {o.id: o.reason for o in full}
        order = placement_order(hierarchy, assets) if cfg.largest_first else hierarchy.sequence()
        nodes = hierarchy.by_id()
        across = set(hierarchy.across) | {  # mounted objects hung across from their anchor
            n.id for n in hierarchy.nodes
            if on_wall(hierarchy.support[n.id]) and n.id not in hierarchy.over
            and self._hangs_across(n, hierarchy.functional.get(n.id), nodes, seed, framed)
        }  # fmt: skip
        backed = {  # floor objects a painting or mirror hangs over: against a wall
            hierarchy.functional[n.id] for n in hierarchy.nodes
            if n.category in HANGS_OVER and on_wall(hierarchy.support[n.id])
            and hierarchy.functional.get(n.id) is not None and n.id not in across
        }  # fmt: skip
        faced_widths: dict[str, float] = {}  # floor id -> widest the hierarchy hangs across
        for dep_id in hierarchy.across:
            at = hierarchy.functional.get(dep_id)
            if at is not None and dep_id in assets and hierarchy.support.get(at) == FLOOR:
                width = float(max(assets[dep_id].size[:2]))
                faced_widths[at] = max(faced_widths.get(at, 0.0), width)
        seats_at = seats_of(hierarchy)  # a table's seats, for its wall draws
        timer["assets"] += time.perf_counter() - t0

        for item in order:
            node = item.dependent
            if node.id in kept:
                continue  # fixed where the user put it
            if node.id in overflow:
                stats.dropped.append(Dropped(node.id, node.category, overflow[node.id]))
                continue
            mounted = on_wall(item.support)
            if item.support != FLOOR and not mounted and item.support not in placed:
                stats.dropped.append(
                    Dropped(node.id, node.category, f"its support {item.support} was dropped")
                )
                continue
            asset = assets[node.id]
            hung_box = None  # where a towel hangs on its holder (by rule, not drawn)
            if item.support in placed and hangs_on(node.category, placed[item.support].asset):
                holder = placed[item.support]
                under = [p.box for i, p in placed.items() if i != item.support]
                asset, hung_box = hang_clear(asset, holder.asset, holder.box, under,
                                             cfg.tolerances)  # fmt: skip
                if hung_box is None:
                    why = f"hangs on no bar of {item.support} (too wide, or touching it)"
                    stats.dropped.append(Dropped(node.id, node.category, why))
                    continue
            elif item.support != FLOOR and not mounted and cfg.reject and cfg.gravity:
                asset = self._walled_in(node, asset, item.support, placed[item.support], room,
                                        seed)  # fmt: skip
                too_big = no_room_on(asset, placed[item.support].asset)
                if too_big is not None:  # no candidate could rest: do not draw 256
                    stats.dropped.append(
                        Dropped(node.id, node.category, f"{too_big} of {item.support}")
                    )
                    continue
            spot = None
            if item.support == FLOOR or mounted:  # a mounted one's wall: per query below
                support = Anchor.floor(bounds)
            else:
                sp = placed[item.support]
                support = Anchor(sp.asset.category, sp.box, asset=sp.asset)
                if cfg.spots and self.spots is not None and framed and hung_box is None:
                    spot = self.spots.check(node.category, sp.asset.category, sp.box,
                                            asset_seed(node.id, seed), asset.size)  # fmt: skip
            functional = check = None
            seats = self._seats(node, seats_at)
            if item.functional is not None and item.functional in placed:
                fp = placed[item.functional]
                functional = Anchor(fp.asset.category, fp.box, asset=fp.asset)
                if item.support == FLOOR and cfg.anchors and self.anchors is not None and framed:
                    check = self.anchors.check(node.category, fp.asset.category, fp.box,
                                               asset_seed(node.id, seed))  # fmt: skip
                if node.id in hierarchy.facing:  # "two sofas facing each other"
                    check = AnchorCheck(fp.box, FACING_GAP_M, must_face=True, in_front=True,
                                        min_gap=FACING_MIN_GAP_M)  # fmt: skip
            over = None  # the wall behind the floor object it hangs over, when it does
            if mounted and node.id in hierarchy.over and functional is not None:
                behind = wall_contact(functional.box, walls_of(room.floor_polygon))
                if behind is not None and wall_index(item.support) in (None, behind.wall):
                    over = behind.wall
            region = None
            if item.support == FLOOR and cfg.reject and cfg.confine:
                region = floor_region(room, asset.size, cfg.floor_repair_m + cfg.wall_snap_m)
            query = PlacementQuery(node.category, asset.size, support, functional, bounds,
                                   asset=asset, region=region)  # fmt: skip
            queries = [(query, None)]
            turned = False  # stands sideways to its wall, if it stands against one
            cornered = False  # stands in the corner at its left (a shower cubicle)
            across_wall = False  # stands with an end to its wall (a shower panel)
            corner_gap = CORNER_GAP_M  # how far short of the next wall it is slid
            if item.support == FLOOR:
                cornered = cfg.closed_by_walls and closed_by_walls(node.category, asset.size)
                across_wall = cfg.end_to_wall and end_to_wall(node.category, asset.size)
                if across_wall:  # its ends: its back and front, or its sides
                    turned = bool(asset.size[1] < asset.size[0])
                    corner_gap = float(np.random.default_rng([asset_seed(node.id, seed), 193])
                                       .uniform(*ENCLOSURE_M))  # fmt: skip
                else:
                    turned = (node.id not in backed and not cornered and self._sideways(
                        node, room, seed, asset.size, self._anchored(functional), seats
                    ))  # fmt: skip
                backs = node.id in backed or cornered or across_wall
                if node.id not in hierarchy.mid_room:
                    queries = self._wall_queries(query, node, room, placed, seed, check,
                                                 backs, turned, seats) or queries  # fmt: skip
            elif mounted:
                queries = self._mount_queries(query, node, item.support, room, placed, seed,
                                              dressed, over, node.id in across,
                                              node.id in hierarchy.across)  # fmt: skip
                if not queries:
                    why = ("no window left for it" if node.category in WINDOW_DRESSINGS
                           else "no wall of the room")  # fmt: skip
                    stats.dropped.append(Dropped(node.id, node.category, why))
                    continue
            on_floor_ = item.support == FLOOR
            ref_yaw = 0.0 if on_floor_ or mounted else placed[item.support].box.yaw
            snap = cfg.snap_yaw_deg if on_floor_ else cfg.snap_yaw_support_deg
            shape = Shape(asset)
            ids = list(placed)  # fixed while this object's candidates are tried
            others = stacked.snapshot()
            context = _Context(item.support, placed, room, doors, others, ids, shape, world,
                               contact_rectangle(asset), guard, check, spot=spot)  # fmt: skip
            context.below_top = support.category in self.top_free
            tilt = self._tilt(node.category, asset_seed(node.id, seed)) if on_floor_ else 0.0
            if node.id in hierarchy.mid_room:  # an island: clear of the walls, alone or not
                context.clear_of = walls_of(room.floor_polygon)
            elif on_floor_ and not self._may_stand_alone(node.category,
                                                         asset_seed(node.id, seed)):  # fmt: skip
                context.company = [floor_outline(placed[i].box) for i in floor_ids]
            context.push_attempts = cfg.push_attempts
            if dense and cfg.dense_push_attempts is not None:
                context.push_attempts = cfg.dense_push_attempts
            context.hanging = hung_box
            if mounted and node.category not in WINDOW_DRESSINGS:
                context.standing = outlines([placed[i].box for i in ids if i not in hung])
                if (
                    cfg.wall_spacing
                    and self.walls is not None
                    and self.walls.keeps_apart(asset_seed(node.id, seed))
                ):
                    context.apart = shown
            elif not mounted:
                context.shown = shown
            if on_floor_ and cfg.separate_footprints and self.overlaps is not None:
                context.floor = self.overlaps.check(
                    node.category,
                    [(i, placed[i].asset.category, placed[i].box) for i in floor_ids],
                )
            if over is not None:
                context.over = functional.box
            if mounted and framed and cfg.mount_heights and self.heights is not None:
                context.heights = self.heights
            hung_across = None if node.id not in across or functional is None else functional.box
            width = faced_widths.get(node.id) if on_floor_ else None
            if width is not None:  # it must face a wall the object hung across fits on
                context.across_walls = walls_with_room(walls_of(room.floor_polygon), room, width)
            along_wall = on_floor_ and framed and queries[0][1] is not None
            context.sideways = along_wall and turned
            context.turn_free = node.category in TURN_FREE
            context.end_to_wall = across_wall
            context.corner_gap = corner_gap
            context.left_corner = cornered
            ends = None  # the room's convex corners, when this object stands in one
            if (
                along_wall
                and cfg.corners
                and (not context.sideways or across_wall)
                and self.walls is not None
                and (
                    cornered
                    or across_wall
                    or self.walls.in_corner(
                        room.type,
                        node.category,
                        asset_seed(node.id, seed),
                        asset.size,
                        anchored=self._anchored(functional),
                        under=self._under(node.id in backed),
                        seats=seats,
                    )
                )
            ):
                ends = convex_ends(walls_of(room.floor_polygon))
            accepted = None
            own: dict[str, int] = {}
            tried = 0
            limit = "dense_give_up" if on_floor_ else "dense_give_up_support"
            give_up = getattr(cfg, limit) if dense else None
            give_up = math.inf if give_up is None else give_up  # (None: never)
            missed = 0  # candidates rejected for want of room
            strays: list[OrientedBox] = []  # drawn candidates rejected only as off_spot
            halves: list[tuple] = []  # (candidate, wall, corner) rejected only as wrong_half
            unseated: list[OrientedBox] = []  # drawn candidates turned from or off their anchor
            unfacing: list[OrientedBox] = []  # drawn candidates not face to face with it
            crossed: list[OrientedBox] = []  # drawn candidates rejected only as crosswise
            crowded: list[tuple] = []  # (candidate, wall, across) rejected only as crowded
            windowed: list[tuple] = []  # (candidate, wall, across) rejected only as window
            unfaced: list[tuple] = []  # (candidate, wall, corner) rejected as no_wall_across
            lonely: list[tuple] = []  # (candidate, wall, corner) rejected only as isolated
            walled: list[tuple] = []  # (candidate, wall, corner) rejected as at_wall
            covering = None  # the first candidate that passed all but covering a wall object
            for k, (q, wall) in enumerate(queries):  # a wall at a time, each its share
                n_q = n // len(queries) + (1 if k < n % len(queries) else 0)
                dressing = wall if isinstance(wall, _Dressing) else None
                context.wall = wall if framed and not mounted else None
                context.mount = (wall if dressing is None else dressing.wall) if mounted else None
                context.dressing = dressing
                context.across = None  # tested only on a wall its anchor faces
                if hung_across is not None and faced_by(context.mount, hung_across):
                    context.across = hung_across
                context.corner = None if ends is None or wall is None else ends[wall.index]
                t0 = time.perf_counter()
                if dressing is not None:  # curtains at a window: by rule
                    boxes, mass = [dressing.box.to_vector()], None
                    want = assets[node.id]
                    if not np.allclose(dressing.box.size, want.size):  # cut to the window
                        want = generate(node.category, dressing.box.size,
                                        want.extra.get("seed", 0))  # fmt: skip
                    if want is not asset:
                        asset, shape = want, Shape(want)
                        context.shape = shape
                elif hung_box is not None:  # a towel on its holder: by rule
                    boxes, mass = [hung_box.to_vector()], None
                else:
                    temperature = (
                        cfg.temperature if on_floor_ or mounted else cfg.support_temperature
                    )
                    boxes, mass = self.model.draw(q, n_q, temperature, generator)
                if k == 0 and region is not None and mass is not None:
                    stats.outside_mass.append(1.0 - mass)
                timer["model"] += time.perf_counter() - t0

                t0 = time.perf_counter()
                if missed >= give_up:
                    boxes = boxes[:0]  # drawn (for the generator), not tried
                for index, vec in enumerate(boxes):
                    # upright (the drawn 6D rotation's heading), at the asset's size
                    yaw = upright_yaw(sixd_x_axis(vec[6:12]), ref_yaw, snap)
                    if tilt and (context.wall is None or context.turn_free):  # as left
                        # (the yaw read back from its matrix, as a box's yaw property is)
                        yaw = float(matrix_to_yaw(yaw_to_matrix(yaw))) + tilt
                    box = OrientedBox(vec[:3], asset.size, yaw_to_matrix(yaw))
                    if not cfg.reject:
                        box, moved = self._unjudged(box, context)
                        accepted = (tried + index, box)
                        stats.repaired += int(moved)
                        break
                    for corner, tried_box in _variants(box, context):
                        settled, reason, moved = self._settle_candidate(tried_box, context)
                        if reason is None:
                            break
                        if reason == "covers" and covering is None:
                            covering = (tried + index, settled, moved)
                        if corner is not None and reason in NO_ROOM:  # taken, not misdrawn
                            misses = context.corner_misses
                            misses[corner] = misses.get(corner, 0) + 1
                    if reason is not None:
                        own[reason] = own.get(reason, 0) + 1
                        if reason == "off_spot" and len(strays) < SPOT_RETRIES:
                            strays.append(box)
                        if reason == "wrong_half" and len(halves) < HALF_RETRIES:
                            halves.append((box, context.wall, context.corner))
                        if reason in SEAT_REASONS and len(unseated) < SEAT_RETRIES:
                            unseated.append(box)
                        if (reason in FACING_REASONS and node.id in hierarchy.facing
                                and len(unfacing) < SEAT_RETRIES):  # fmt: skip
                            unfacing.append(box)
                        if reason == "crosswise" and len(crossed) < CROSS_RETRIES:
                            crossed.append(box)
                        if reason == "crowded" and len(crowded) < CROWD_RETRIES:
                            crowded.append((box, context.mount, context.across))
                        if reason == "no_wall_across" and len(unfaced) < ACROSS_RETRIES:
                            unfaced.append((box, context.wall, context.corner))
                        if (
                            reason == "window"
                            and mounted
                            and dressing is None
                            and len(windowed) < WINDOW_RETRIES
                        ):
                            windowed.append((box, context.mount, context.across))
                        if reason == "isolated" and len(lonely) < LONELY_RETRIES:
                            lonely.append((box, context.wall, context.corner))
                        if reason == "at_wall" and len(walled) < LONELY_RETRIES:
                            walled.append((box, context.wall, context.corner))
                        missed += reason in NO_ROOM
                        if missed >= give_up:
                            boxes = boxes[: index + 1]  # (counted as tried)
                            break
                        continue
                    accepted = (tried + index, settled)
                    stats.repaired += int(moved)
                    break
                tried += len(boxes)
                timer["collision"] += time.perf_counter() - t0
                if accepted is not None:
                    break
            if accepted is None and strays:  # the model's draws all off the spot: move some
                t0 = time.perf_counter()
                for box in strays:
                    settled, why, _ = self._settle_candidate(spot.onto(box), context)
                    if why is None:
                        accepted = (tried, settled)
                        stats.repaired += 1
                        break
                    if why == "covers" and covering is None:
                        covering = (tried, settled, True)
                timer["collision"] += time.perf_counter() - t0
            lifted = functools.partial(self._lifted, context, tried, stats, timer)
            if accepted is None and crossed:  # none the drawn way: the other will do
                assert context.spot is not None
                spot = replace(context.spot, parallel=None)
                accepted = lifted(crossed, None, spot=spot)
            if accepted is None and crowded:  # none apart from the others: close will do
                accepted = lifted(crowded, _as_hung, apart=None)
            if accepted is None and unfaced:  # none faces a wall with room: as drawn will do
                accepted = lifted(unfaced, _as_drawn, across_walls=None)
            if accepted is None and windowed:  # every draw over a window: beside it will do
                slid = [(b, wall, across) for box, wall, across in windowed
                        for b in self._beside_windows(box, wall, room)]  # fmt: skip
                accepted = lifted(slid, _as_hung)
            if accepted is None and lonely:  # none near a wall or another: alone will do
                accepted = lifted(lonely, _as_drawn, company=None)
            if accepted is None and walled:  # none clear of the walls: by one will do
                accepted = lifted(walled, _as_drawn, clear_of=None)
            if accepted is None and halves:  # none by the drawn half: the other will do
                assert context.anchor is not None
                accepted = lifted(halves, _as_drawn, anchor=replace(context.anchor, half=0))
            if (
                accepted is None
                and unseated
                and cfg.seat_at_anchor
                and context.anchor is not None
                and context.anchor.must_face
            ):  # turned from or off its anchor: seated at it
                at = context.anchor.anchor
                seated = [(seated_at(b, at), None, None) for b in unseated]  # (wherever the walls)
                accepted = lifted(seated, _as_drawn)
            if accepted is None and unfacing:  # none face to face: set across from it
                assert context.anchor is not None
                at = context.anchor.anchor
                across = [(facing_at(b, at), None, None) for b in unfacing]
                accepted = lifted(across, _as_drawn)
            if accepted is None and covering is not None:  # better than not there at all
                index, settled, moved = covering
                accepted = (index, settled)
                stats.repaired += int(moved)
            for reason, count in own.items():
                rejections[reason] = rejections.get(reason, 0) + count
            if accepted is None:
                why = ", ".join(f"{k} {v}" for k, v in sorted(own.items(), key=lambda kv: -kv[1]))
                reason = f"no valid placement among {tried} candidates ({why})"
                if missed >= give_up:
                    reason += f"; gave up after {give_up} for want of room ({_flag(limit)})"
                if on_floor_ and _too_large(asset.size, room):
                    reason = (f"too large for the room ({asset.size[0]:.2f} x "
                              f"{asset.size[1]:.2f} m)")  # fmt: skip
                stats.dropped.append(Dropped(node.id, node.category, reason))
                continue
            index, box = accepted
            support_id = item.support
            if mounted:
                support_id = wall_support(context.mount.index)
                hung.add(node.id)
                if context.dressing is not None:
                    dressed.add(context.dressing.window)
                elif node.category not in WINDOW_DRESSINGS:
                    shown.append((node.id, box, context.mount))
            shape.set_pose(box.rotation, box.center)
            world.add(node.id, shape)
            placed[node.id] = _Placed(box, asset)
            stacked.add(box.center, box.half_size, box.rotation)
            if item.support == FLOOR:
                floor_ids.append(node.id)
                if guard is not None:
                    guard.add(box)
            stats.resamples.append(index)
            objects.append(
                SceneObject(
                    node.id, node.category, box,
                    AssetRef(asset.source, asset.asset_id, asset.style, asset.extra.get("seed")),
                    support=support_id,
                    functional_anchor=item.functional if item.functional in placed else None,
                )
            )  # fmt: skip
        stats.placed = len(objects) - len(kept)
        stats.seconds = {**timer, "total": time.perf_counter() - start}
        scene = Scene(scene_id, room, objects, source="pair2scene", stats=stats.to_dict())
        return Placement(scene, stats, {oid: p.asset for oid, p in placed.items()})

    def _wall_queries(
        self, query, node, room: Room, placed: dict[str, _Placed], seed: int,
        check: AnchorCheck | None = None, backed: bool = False, turned: bool = False,
        seats: int | None = None,
    ) -> list:  # fmt: skip
        """(``query`` in a wall's frame, the wall) once per wall to try, best first
        (:func:`wall_order`), when the wall rules put this floor object against a wall
        (always when a painting or mirror hangs over it: ``backed``; ``seats``: as
        :meth:`_seats` gives it) and a wall has room for it (``turned``: for its side,
        :meth:`_sideways`); else []."""
        if self.walls is None or not self.config.walls:
            return []
        seed_ = asset_seed(node.id, seed)
        size = np.asarray(query.size, float)
        anchored = self._anchored(query.functional)
        if not backed and not self.walls.against_wall(
            room.type, node.category, seed_, size,
            anchored=anchored, under=self._under(False), seats=seats,
        ):  # fmt: skip
            return []
        width, depth = size[:2]  # along the wall and into the room
        if turned:
            width, depth = depth, width
        walls = walls_of(room.floor_polygon)
        boxes = _floor_boxes(placed)
        free = [free_length(free_stretches(w, room, boxes, depth, size[2]), width) for w in walls]
        if check is not None and not check.across:
            gap = check.max_gap + self.config.wall_snap_m
            free = [f if within_reach(w, check.anchor, depth, gap, width, check.must_face)
                    else 0.0 for w, f in zip(walls, free)]  # fmt: skip
            if not any(f > 0 for f in free):
                return []  # no wall near its anchor: drawn at the anchor instead
        rng = np.random.default_rng([seed_, 181])
        anchor = distance = None
        if query.functional is not None:
            anchor = query.functional.box
            distance = self.walls.distance(node.category, query.functional.category)
        in_front = check is not None and check.in_front
        order = wall_order(walls, free, rng, anchor, distance, in_front)
        return [(replace(query, wall=walls[i].frame(room.height)), walls[i]) for i in order]

    def _sideways(
        self, node, room: Room, seed: int, size, anchored: bool | None, seats: int | None
    ) -> bool:
        """Whether floor object ``node`` of box ``size``, if it stands against a wall,
        stands sideways to it (:attr:`AssemblyConfig.sideways`; a draw of the wall
        rules; ``anchored`` and ``seats`` as :meth:`_anchored` and :meth:`_seats` give
        them; asked only of objects no wall object hangs over)."""
        return (
            self.config.sideways
            and self.walls is not None
            and self.walls.turned(
                room.type,
                node.category,
                asset_seed(node.id, seed),
                size,
                anchored=anchored,
                under=self._under(False),
                seats=seats,
            )
        )

    def _seats(self, node, seats_at: Counter) -> int | None:
        """How many seats take a floor object of :data:`~pair2scene.categories.SEATED_AT`
        as their anchor in the hierarchy, for the wall rules' shares
        (:attr:`AssemblyConfig.split_seats`); None: not asked."""
        if not self.config.split_seats or node.category not in SEATED_AT:
            return None
        return seats_at[node.id]

    def _anchored(self, functional: object | None) -> bool | None:
        """Whether a floor object's functional anchor stands in the room, for the wall
        rules' shares (:attr:`AssemblyConfig.split_wall_rates`); None: not asked."""
        return (functional is not None) if self.config.split_wall_rates else None

    def _under(self, hung_over: bool) -> bool | None:
        """Whether a painting, mirror or wall lamp hangs over a floor object, for the wall
        rules' shares (:attr:`AssemblyConfig.split_hung_over`); None: not asked."""
        return hung_over if self.config.split_hung_over else None

    def _hangs_across(self, node, anchor: str | None, nodes: dict, seed: int, framed: bool) -> bool:
        """Whether mounted ``node`` hangs across the room from its floor anchor ``anchor``
        (an id of ``nodes``; :meth:`AnchorRules.across
        <pair2scene.assembly.anchors.AnchorRules.across>`): never without the anchor rules
        (:attr:`AssemblyConfig.anchors`)."""
        if anchor is None or not (self.config.anchors and self.anchors is not None and framed):
            return False
        return self.anchors.across(node.category, nodes[anchor].category,
                                   asset_seed(node.id, seed))  # fmt: skip

    def _mount_queries(
        self, query, node, support: str, room: Room, placed: dict[str, _Placed], seed: int,
        dressed: set[int], over: int | None = None, across: bool = False,
        only_faced: bool = False,
    ) -> list:  # fmt: skip
        """(``query`` on a wall, the wall) once per wall to try (:func:`mount_order`); for
        curtains and blinds (None, a :class:`_Dressing`) once per window not yet dressed.
        ``over``: the index of the only wall to try (the one behind the floor object it
        hangs over); ``across``: the walls its functional anchor faces first, and with
        ``only_faced`` (the hierarchy hangs it there: "a TV opposite the sofa") only
        those, when the anchor faces any."""
        from pair2scene.model.api import Anchor

        walls = walls_of(room.floor_polygon)
        rng = np.random.default_rng([asset_seed(node.id, seed), 191])
        if node.category in WINDOW_DRESSINGS:
            floor = _floor_boxes(placed)
            hung = [p.box for p in placed.values() if p.asset.category in WINDOW_DRESSINGS]
            out = []
            for i, window in enumerate(room.windows):
                if i in dressed:
                    continue
                for wall in walls:
                    if wall_index(support) not in (None, wall.index):
                        continue
                    box = dress_window(window, wall, query.size, room.height,
                                       self.config.ceiling_margin_m)  # fmt: skip
                    if box is None:
                        continue
                    share = dressing_share(window, wall, room)
                    lo, hi = wall.extent(box)
                    if lo >= share[0] - 1e-9 and hi <= share[1] + 1e-9:  # (else: cut only)
                        out.append((None, _Dressing(wall, i, box)))
                    cut = fitted_dressing(window, wall, box, room, floor, hung)
                    if cut is not None:  # furniture under it, a door or curtains beside it
                        out.append((None, _Dressing(wall, i, cut)))
            return out
        anchor = None if query.functional is None else query.functional.box
        only = wall_index(support) if over is None else over
        order = mount_order(walls, rng, anchor, only, across, only_faced)
        return [(replace(query, support=Anchor.wall(w.frame(room.height))), w) for w in order]

    def _settle_candidate(
        self, box: OrientedBox, ctx: _Context
    ) -> tuple[OrientedBox | None, str | None, bool]:
        """The candidate at rest (dropped, nudged onto its surface or into the room, pushed
        out of a shallow collision), the reason it cannot stay, and whether it was moved."""
        cfg = self.config
        if ctx.mount is not None:
            return self._hang_candidate(box, ctx)
        if ctx.hanging is not None:  # a towel on its holder: where the rule hung it
            reason, _ = self._blocked(box, ctx) if cfg.reject else (None, [])
            return (None, reason, False) if reason is not None else (box, None, False)
        moved = False
        for attempt in range(ctx.push_attempts + 1):
            rested, reason, shifted = self._rest(box, ctx)
            if reason is not None:
                return None, reason, moved
            moved |= shifted
            if rested.top > ctx.room.height - cfg.ceiling_margin_m:
                return None, "ceiling", moved
            if not cfg.gravity and rested.bottom < -cfg.tolerances.touch:
                return None, "floor", moved  # nothing dropped it: it may have sunk
            reason, hits = self._blocked(rested, ctx)
            if reason is None:
                if ctx.across_walls is not None and not any(
                    faced_by(wall, rested) for wall in ctx.across_walls
                ):
                    return None, "no_wall_across", moved
                return rested, None, moved
            if reason == "covers":  # the placer keeps it when nothing better comes
                return rested, reason, moved
            pushed = ("collision", "door", "wall", "overlap")
            if reason not in pushed or attempt == ctx.push_attempts:
                return None, reason, moved
            if reason == "wall":  # back into the room, as a floor object would be
                inside = into_room(rested, ctx.room.floor_polygon, self._repair(ctx))
                push = np.zeros(3) if inside is None else inside.center - rested.center
            elif reason in ("door", "overlap"):  # out of the swing, or from under a table
                boxes = [ctx.doors[0][i] if reason == "door" else ctx.placed[i].box for i in hits]
                mine = footprint(rested)[1:]
                push = clearing_move([(mine, footprint(b)[1:]) for b in boxes])
            else:
                ctx.shape.set_pose(rested.rotation, rested.center)
                push = ctx.world.push_out(ctx.shape, hits)
            if not push.any() or np.linalg.norm(push) > self._repair(ctx):
                return None, reason, moved
            center = rested.center + push
            box, moved = OrientedBox(center, rested.size, rested.rotation), True
        return None, "collision", moved  # unreachable: the loop returns

    def _lifted(
        self, ctx: _Context, tried: int, stats: AssemblyStats, timer: dict, candidates: list,
        place=None, **lift,
    ) -> tuple[int, OrientedBox] | None:  # fmt: skip
        """:meth:`_retried` of ``candidates`` once ``ctx`` has the fields of ``lift`` (the
        preference they were rejected for lifted), its time counted as collision time."""
        t0 = time.perf_counter()
        for name, value in lift.items():
            setattr(ctx, name, value)
        accepted = self._retried(candidates, ctx, tried, stats, place)
        timer["collision"] += time.perf_counter() - t0
        return accepted

    def _retried(
        self, candidates: list, ctx: _Context, tried: int, stats: AssemblyStats, place=None
    ) -> tuple[int, OrientedBox] | None:
        """(index, box) of the first of ``candidates`` (drawn ones rejected only for a
        preference the caller has since lifted from ``ctx``: the drawn half of the anchor,
        the drawn way across the support, keeping apart on the wall) that passes, each
        tried through its :func:`_variants`, or None. ``place(candidate, ctx)`` sets
        ``ctx`` as the candidate was drawn (:func:`_as_drawn`, :func:`_as_hung`) and gives
        its box."""
        for candidate in candidates:
            box = candidate if place is None else place(candidate, ctx)
            for _, tried_box in _variants(box, ctx):
                settled, why, moved = self._settle_candidate(tried_box, ctx)
                if why is None:
                    stats.repaired += int(moved)
                    return tried, settled
        return None

    def _beside_windows(self, box: OrientedBox, wall, room: Room) -> list[OrientedBox]:
        """Drawn ``box`` hung on ``wall`` (:func:`mount`) and slid beside the windows it
        covers, nearer side first (:func:`clear_of_windows`); empty where it cannot hang."""
        hung = mount(box, wall, room.height, self.config.ceiling_margin_m)
        return [] if hung is None else clear_of_windows(hung, wall, room)

    def _hang_candidate(
        self, box: OrientedBox, ctx: _Context
    ) -> tuple[OrientedBox | None, str | None, bool]:
        """A mounted object's candidate hung on its wall (:func:`mount`; curtains as
        :func:`dress_window` put them) and why it cannot stay: ``too_large`` for the wall,
        ``off_height``, ``not_in_front``, :func:`mount_blocked`'s reasons, ``hidden``,
        ``crowded`` (:func:`~pair2scene.assembly.mounting.crowds`, when kept apart),
        ``collision`` (never pushed: it must stay on the wall where it was drawn)."""
        cfg = self.config
        dressing = ctx.dressing is not None
        hung = box if dressing else mount(box, ctx.mount, ctx.room.height, cfg.ceiling_margin_m)
        if hung is None:
            return None, "too_large", False
        if ctx.over is not None and not dressing:
            hung = hang_over(hung, ctx.mount, ctx.over)
        if not cfg.reject:
            return hung, None, False
        if not dressing and ctx.heights is not None:
            if ctx.heights.off_height(ctx.shape.asset.category, hung):
                return None, "off_height", False
        if ctx.across is not None and not faces(ctx.across, hung):
            return None, "not_in_front", False
        floor = _floor_boxes(ctx.placed, ctx.ids)
        reason = mount_blocked(hung, ctx.mount, ctx.room, dressing, floor)
        if reason is None and ctx.standing is not None:  # (None: curtains, blinds)
            shares = covered_shares(hung, ctx.mount, *ctx.standing)
            if (shares > MAX_COVER).any():
                reason = "hidden"  # behind what stands in front of it (a vase, a lamp)
        if reason is None and ctx.apart is not None and crowds(hung, ctx.mount, ctx.apart):
            reason = "crowded"  # within CLOSE_WALL_M of another on its wall
        if reason is None:
            reason, _ = self._blocked(hung, ctx)
        return (None, reason, False) if reason is not None else (hung, None, False)

    def _rest(self, box: OrientedBox, ctx: _Context) -> tuple[OrientedBox | None, str | None, bool]:
        """The candidate dropped onto what carries it (nudged at most ``repair_m``), or
        (None, why not); and whether it was nudged."""
        cfg = self.config
        if ctx.support == FLOOR:
            box = dropped(box, 0.0) if cfg.gravity else box
            inside = into_room(box, ctx.room.floor_polygon, cfg.floor_repair_m, cfg.wall_snap_m)
            if inside is None:
                return None, "outside", False
            return inside, None, inside is not box
        if not cfg.gravity:
            return box, None, False  # where drawn, carried or not
        sp = ctx.placed[ctx.support]
        rest = rest_on_surfaces(sp.asset, sp.box, box, contact=ctx.contact,
                                max_shift=cfg.repair_m, top=not ctx.below_top)  # fmt: skip
        if rest is None:
            return None, "unsupported", False
        z, shift = rest
        box = dropped(box, z)
        if shift.any():
            center = box.center.copy()
            center[:2] += shift
            box = OrientedBox(center, box.size, box.rotation)
        return box, None, bool(shift.any())

    def _unjudged(self, box: OrientedBox, ctx: _Context) -> tuple[OrientedBox, bool]:
        """The no-rejection ablation's object: at rest (nudged) when gravity is on and
        something carries it, else where drawn (a floor object on the floor when gravity
        is on); and whether it was nudged. Nothing is tested against the room or others."""
        if ctx.mount is not None:  # hung on its wall, wherever that puts it
            hung = self._hang_candidate(box, ctx)[0]
            return (box, False) if hung is None else (hung, False)
        if ctx.hanging is not None:  # a towel on its holder
            return box, False
        if not self.config.gravity:
            return box, False
        rested, _, shifted = self._rest(box, ctx)
        if rested is not None:
            return rested, shifted
        return (dropped(box, 0.0) if ctx.support == FLOOR else box), False

    def _tilt(self, category: str, seed: int) -> float:
        """The turn (radians, either way) off the walls' axes of a free-standing floor object
        of ``category`` (``seed``: its asset seed), drawn with the category's shares
        (:attr:`askew`), uniform within its bin; 0 for a square one or an unknown
        category."""
        shares = self.askew.get(category)
        if shares is None or not self.config.askew:
            return 0.0
        rng = np.random.default_rng([seed, ASKEW_SALT])
        b = int(rng.choice(len(shares), p=shares))
        if b == 0:
            return 0.0
        low, high = ASKEW_BINS_DEG[b - 1], ASKEW_BINS_DEG[b]
        return float(np.radians(rng.uniform(low, high)) * rng.choice((-1.0, 1.0)))

    def _may_stand_alone(self, category: str, seed: int) -> bool:
        """Whether a floor object of ``category`` (``seed``: its asset seed) may stand
        alone in the room, drawn with its category's share (:attr:`isolated`); True for a
        category without one, or with the rule off."""
        share = self.isolated.get(category)
        if share is None or not self.config.isolation:
            return True
        return bool(np.random.default_rng([seed, ALONE_SALT]).random() < share)

    def _repair(self, ctx: _Context) -> float:
        return self.config.floor_repair_m if ctx.support == FLOOR else self.config.repair_m

    def _blocked(self, box: OrientedBox, ctx: _Context) -> tuple[str | None, list]:
        """Why a resting candidate cannot stay ("wall": an object on a support reaching
        through a wall, "faces_away" / "not_in_front" / "wrong_half" / "far_from_anchor" /
        "near_anchor": not at its functional anchor as the training rooms' pairs were (or
        as :attr:`Hierarchy.facing <pair2scene.hierarchy.tree.Hierarchy.facing>` asks), "turned" /
        "off_spot": not how or where the training rooms' objects stood on their support,
        "isolated": alone in the room when its category's objects rarely stood so
        (:attr:`_Context.company`), "at_wall": nearer a wall than
        :data:`MID_ROOM_GAP_M` when the hierarchy stands it mid-room, "off_wall": no
        longer against the wall it was drawn against, "side_to_wall": a side, not its back,
        against it when the wall rules did not turn it sideways (:meth:`_sideways`; the
        data's share of sideways objects is drawn there, not left to the model's yaw),
        "along_wall": a shower panel's long face at a wall (:attr:`_Context.end_to_wall`),
        "door", "overlap" (over or under another floor object's footprint,
        :attr:`AssemblyConfig.separate_footprints`: tested before the meshes, a cheaper
        test whose push clears the meshes too), "collision", "blocks_path") and what it
        hits (the doors' indices, the objects' ids)."""
        if ctx.support != FLOOR and not on_floor(box, ctx.room.floor_polygon):
            return "wall", []
        if ctx.spot is not None:
            reason = ctx.spot.reason(box)
            if reason is not None:
                return reason, []
        if ctx.anchor is not None:
            reason = ctx.anchor.reason(box, ctx.wall)
            if reason is not None:
                return reason, []
        if (
            ctx.company is not None
            and ctx.wall is None
            and stands_alone(floor_outline(box), ctx.room.floor_polygon, ctx.company)
        ):
            return "isolated", []  # alone mid-room, as its category's objects rarely stood
        if ctx.clear_of is not None and walls_near(box, ctx.clear_of, MID_ROOM_GAP_M):
            return "at_wall", []  # an island or a table the text put mid-room
        if (
            ctx.wall is not None
            and not face_contacts(box, [ctx.wall], faces=("back",))
            and not (ctx.turn_free and walls_near(box, [ctx.wall]))
        ):
            # (its back against the wall, the usual case, is all :func:`wall_contact`
            # would have preferred: only without it are the other faces asked)
            contact = wall_contact(box, [ctx.wall])
            if contact is None:
                return "off_wall", []  # pushed off the wall it was drawn against
            if not ctx.sideways:
                return "side_to_wall", []  # the wall rules drew it back to the wall
        if ctx.end_to_wall and face_contacts(
            box, walls_of(ctx.room.floor_polygon), ALONG_WALL_M,
            faces=("back", "front") if ctx.sideways else ("left", "right"),
        ):  # fmt: skip
            return "along_wall", []  # a panel lying along a wall closes nothing off
        center, half, rot = box.center[None], box.half_size[None], box.rotation[None]
        if ctx.mount is None and ctx.doors[0]:  # (what rests on a table may overhang it)
            doors = ctx.doors[1].overlaps(center, half, rot)[0]
            if doors.any():
                return "door", list(np.flatnonzero(doors))
        if ctx.floor is not None:
            under = ctx.floor.hits(box)
            if under:
                return "overlap", under  # over or under another floor object's footprint
        hits = ctx.others.overlaps(center, half, rot)[0]
        near = [ctx.ids[j] for j in np.flatnonzero(hits)]
        if near:
            ctx.shape.set_pose(box.rotation, box.center)
            colliding = ctx.world.colliding(ctx.shape, near)
            if colliding:
                return "collision", colliding
        if ctx.support == FLOOR and ctx.guard is not None and ctx.guard.blocks(box):
            return "blocks_path", []  # only candidates that passed the rest
        for oid, face, wall in ctx.shown:  # last: one that only covers may still stand
            if oid != ctx.support and covered_share(face, wall, box) > MAX_COVER:
                return "covers", []  # (what rests on it, a towel on its rail, does not)
        return None, []


def _as_drawn(item: tuple, ctx: _Context) -> OrientedBox:
    """A floor candidate (box, wall, corner) kept for a retry, ``ctx`` set to the wall and
    corner it was drawn at."""
    box, ctx.wall, ctx.corner = item
    return box


def _as_hung(item: tuple, ctx: _Context) -> OrientedBox:
    """A mounted candidate (box, wall, across) kept for a retry, ``ctx`` set to the wall
    it was drawn on and what it hangs across from there."""
    box, ctx.mount, ctx.across = item
    return box


def floor_region(room: Room, size: np.ndarray, reach: float) -> OrientedBox:
    """Where a floor object's drawn centre must be for it to end in the room: the room's
    bounds narrowed by the least half-extent its footprint has along an axis at any yaw
    (half its shorter side) and widened by ``reach``, the farthest :func:`into_room` moves
    a candidate (plus a centimetre). Any candidate drawn outside it is rejected as
    "outside"; a room too narrow leaves an empty (zero-width) region."""
    bounds = room.bounds
    grow = reach + 0.01 - 0.5 * float(min(size[0], size[1]))
    half = np.maximum(bounds.half_size[:2] + grow, 0.0)
    return OrientedBox(bounds.center, np.array([*(2 * half), bounds.size[2]]), bounds.rotation)


def _too_large(size: np.ndarray, room: Room) -> bool:
    """Whether a footprint fits the room's bounding rectangle in neither orientation."""
    extent = np.sort(room.floor_polygon.max(0) - room.floor_polygon.min(0))
    return bool((np.sort(size[:2]) > extent).any())


def _variants(box: OrientedBox, ctx: _Context) -> list[tuple[tuple[int, int] | None, OrientedBox]]:
    """The boxes to try for one drawn candidate, in order, each with the (wall index, end)
    of the corner it was slid into (None for the others): slid into each corner of its
    wall, the nearer one first, when the object is to stand in one
    (:attr:`_Context.corner`, :attr:`_Context.corner_gap` short of the next wall; a corner
    it missed :data:`CORNER_TRIES` times is left out); turned to stand sideways to its wall
    (:attr:`_Context.sideways`; a shower panel only turned, slid into the corners as
    above); moved onto its pinned spot on its support
    (:meth:`~pair2scene.assembly.anchors.SpotCheck.pinned`); then as drawn."""
    if ctx.sideways and ctx.wall is not None:
        turned = turn_sideways(box, ctx.wall, ctx.room.bounds.center)
        if not ctx.end_to_wall:
            return [(None, turned), (None, box)]
        box = turned  # a panel whose sides are its ends: never as drawn, corners as below
    if ctx.corner is not None and ctx.wall is not None:
        index = ctx.wall.index
        if ctx.left_corner:  # its own corner only, as long as it may still pass there
            left = 0 if float(box.rotation[:2, 0] @ ctx.wall.direction) > 0 else 1
            tries = ctx.corner_misses.get((index, left), 0)
            corners = [((index, end), b) for end, b in to_corners(box, ctx.wall, ctx.corner,
                                                                   ctx.corner_gap)
                       if end == left and tries < CLOSED_CORNER_TRIES]  # fmt: skip
            return corners or [(None, box)]
        corners = [((index, end), b) for end, b in to_corners(box, ctx.wall, ctx.corner,
                                                               ctx.corner_gap)
                   if ctx.corner_misses.get((index, end), 0) < CORNER_TRIES]  # fmt: skip
        return [*corners, (None, box)]
    if ctx.spot is not None:
        pinned = ctx.spot.pinned(box)
        if pinned is not None:
            return [(None, pinned), (None, box)]
    return [(None, box)]


@dataclass
class _Context:
    """What one object's candidates are judged against."""

    support: str
    placed: dict
    room: Room
    doors: tuple
    """The door zones (:func:`door_boxes`) and the same as a :class:`BoxSet`."""
    others: BoxSet
    ids: list
    shape: Shape
    world: MeshWorld
    contact: np.ndarray
    guard: FloorGuard | None = None
    """Keeps the floor navigable (None: not asked)."""
    anchor: AnchorCheck | None = None
    """Keeps the object at its functional anchor (None: no rule)."""
    over: OrientedBox | None = None
    """The floor object a mounted one hangs over (:func:`hang_over`; None: where drawn)."""
    across: OrientedBox | None = None
    """The floor object a mounted one hangs across the room from, when it faces the wall
    being tried (there, only where it faces the object: ``not_in_front``); None: no such
    test."""
    spot: SpotCheck | None = None
    """Keeps the object at its spot on its support (None: no rule)."""
    wall: Wall | None = None
    """The wall the candidates are drawn against (None: no wall)."""
    corner: tuple[bool, bool] | None = None
    """Whether the start and the end of ``wall`` are convex corners, when the object is
    to stand in one (None: not asked)."""
    left_corner: bool = False
    """Only the corner at the object's left (-x) side is tried
    (:attr:`AssemblyConfig.closed_by_walls`)."""
    corner_misses: dict = field(default_factory=dict)
    """(wall index, end) -> how many of this object's candidates slid into that corner
    did not pass."""
    sideways: bool = False
    """The object is to stand with a side against ``wall``, not its back."""
    turn_free: bool = False
    """Its turn means nothing (:data:`~pair2scene.categories.TURN_FREE`): turned off the
    walls' axes as the training rooms' were (:meth:`Placer._tilt`) even by a wall, where
    its footprint reaching the wall puts it against it (a pot has no back)."""
    end_to_wall: bool = False
    """The object is a panel to stand across ``wall`` (:attr:`AssemblyConfig.end_to_wall`):
    when ``sideways``, never as drawn (its back, a long face, to the wall); a long face
    near a wall is rejected (``along_wall``)."""
    corner_gap: float = CORNER_GAP_M
    """How far short of the next wall a candidate is slid into a corner (m): 5 mm, or a
    shower panel's enclosure depth (:data:`ENCLOSURE_M`)."""
    apart: list | None = None
    """For a mounted object kept apart: the mounted objects (id, box, wall) it keeps
    :data:`~pair2scene.curation.stats.CLOSE_WALL_M` from on its wall (None: no rule)."""
    across_walls: list[Wall] | None = None
    """A floor object's: the walls it may face, those with room free of doors and windows
    for what the hierarchy hangs across the room from it (None: any)."""
    mount: Wall | None = None
    """The wall a mounted object's candidates hang on (None: not mounted)."""
    heights: MountHeights | None = None
    """The height bands a mounted object keeps to (None: no rule)."""
    below_top: bool = False
    """Rest on the support's surfaces below its top (:attr:`Placer.top_free`)."""
    floor: FloorCheck | None = None
    """The floor objects a floor object may not stand over or under (None: no rule)."""

    dressing: _Dressing | None = None
    """Where curtains or blinds hang (None: not a window dressing)."""
    hanging: OrientedBox | None = None
    """Where a towel hangs on its holder (:func:`~pair2scene.assembly.hanging.hang`;
    None: not a towel on a holder)."""
    shown: list = field(default_factory=list)
    """(id, box, wall) of the wall objects placed so far that must stay in view (curtains
    and blinds excepted): a candidate covering more than :data:`MAX_COVER` of one's face,
    unless it rests on it, is rejected (``covers``), and kept only when none of the
    object's candidates does better."""
    standing: tuple | None = None
    """A mounted object's (not curtains or blinds): the :func:`~.mounting.outlines` of what
    stands in the room (everything placed but wall objects); a candidate more than
    :data:`MAX_COVER` of whose face they cover is ``hidden``."""
    push_attempts: int = 5
    """Push-outs a candidate may take (:attr:`AssemblyConfig.push_attempts`, or
    ``dense_push_attempts`` in a ``beyond`` scene)."""
    company: list | None = None
    """For a floor object that may not stand alone (:attr:`AssemblyConfig.isolation`):
    the footprints of the floor objects placed before it; a candidate further than
    :data:`~pair2scene.scene.relations.ALONE_M` from all of them and from every wall is
    ``isolated`` (None: no rule)."""
    clear_of: list | None = None
    """For a floor object the hierarchy stands mid-room (:attr:`Hierarchy.mid_room
    <pair2scene.hierarchy.tree.Hierarchy.mid_room>`): the room's walls, which a candidate
    may come no nearer than :data:`MID_ROOM_GAP_M` (``at_wall``; None: no rule)."""


@dataclass(frozen=True)
class _Dressing:
    """A window that curtains or blinds are to hang at: its wall, its index in the room
    and their box there (:func:`dress_window`)."""

    wall: Wall
    window: int
    box: OrientedBox


FLOOR_BOX_BOTTOM_M = 0.05
"""An object whose bottom is this low stands on the floor (what a mounted object may hang
behind or above)."""


def _floor_boxes(placed: dict[str, _Placed], ids=None) -> list[OrientedBox]:
    """The boxes of the placed objects (of ``ids``, default all) standing on the floor
    (:data:`FLOOR_BOX_BOTTOM_M`)."""
    return [placed[i].box for i in (placed if ids is None else ids)
            if placed[i].box.bottom < FLOOR_BOX_BOTTOM_M]  # fmt: skip


PERIMETER_PER_SEAT_M = 0.8
"""Edge of a table each chair at it takes at the least (:func:`seats_fit`): all but 2 of
the 176 training rooms' dining tables with two or more chairs at them gave each at least
this much of their perimeter (the two: six chairs round a 1.37 x 0.70 m table, 0.69 m
each); the fewest four chairs had was 0.99 m each, six 0.69."""


def seats_of(hierarchy: Hierarchy) -> Counter[str]:
    """Object id -> how many seats (:data:`~pair2scene.categories.SEATS`) standing on the
    floor take it as their functional anchor in ``hierarchy``."""
    return Counter(
        hierarchy.functional[n.id] for n in hierarchy.nodes
        if n.category in SEATS and hierarchy.support[n.id] == FLOOR
        and hierarchy.functional.get(n.id) is not None
    )  # fmt: skip


MIN_ISLAND_M = 1.2
"""Shortest counter drawn for an island (:func:`mid_room_fit`): 13 of the 18 training
kitchens' floor counters standing 0.3 m or more from every wall were 1.14-4.35 m long, the
other five 0.5-0.71 m pieces."""


def mid_room_fit(category: str):
    """A test of sizes (K, 3) -> (K,) bool: which suit ``category``'s object standing clear
    of every wall: built in no particular form (:func:`~pair2scene.assets.forms.form_of`;
    a counter that stands free is a straight run, not an L or a C of cabinets, which
    stand in corners) and, for a counter, at least :data:`MIN_ISLAND_M` long."""

    def fits(sizes: np.ndarray) -> np.ndarray:
        sizes = np.asarray(sizes, float)
        plain = np.array([form_of(category, size) is None for size in sizes], bool)
        if category == "counter_top":
            plain &= sizes[:, :2].max(1) >= MIN_ISLAND_M
        return plain

    return fits


def seats_fit(seats: int):
    """A test of sizes (K, 3) -> (K,) bool: which seat ``seats`` chairs round their edge,
    :data:`PERIMETER_PER_SEAT_M` each; the one of the longest perimeter when none does.
    Sizes were drawn for tables whatever their chairs: in 100 fit rooms of each type five
    chairs stood round a 0.72 m table, and the tables with four or five chairs had a
    median long side of 1.31-1.47 m, where the training rooms' had 1.78 m."""

    def fits(sizes: np.ndarray) -> np.ndarray:
        perimeter = 2 * np.asarray(sizes, float)[:, :2].sum(1)
        ok = perimeter >= seats * PERIMETER_PER_SEAT_M
        return ok if ok.any() else perimeter == perimeter.max()

    return fits


FACING_GAP_M = 3.0
"""Farthest a floor object the hierarchy stands facing its anchor (:attr:`Hierarchy.facing
<pair2scene.hierarchy.tree.Hierarchy.facing>`: "two sofas facing each other") may stand
from it, footprint to footprint: across a coffee table and a walkway, not across a hall."""
FACING_MIN_GAP_M = 1.0
"""Nearest it may stand: a coffee table's depth (0.5-0.6 m) and knee room either side
(without it, 6 of 10 pairs of sofas "facing each other" stood front to front, touching)."""

MID_ROOM_GAP_M = 0.6
"""Floor kept between a mid-room object (:attr:`Hierarchy.mid_room
<pair2scene.hierarchy.tree.Hierarchy.mid_room>`: "a kitchen island") and every wall: a
walkway, half again an agent's width at the default radius (0.4 m)."""

FIT_MARGIN = 0.9
"""Share of a surface's extent a dependent's footprint may take when the data says no
more (:func:`surface_fit`)."""


def surface_fit(support: Asset, margin: float = FIT_MARGIN):
    """A test of sizes (K, 3) -> (K,) bool: which fit on one of ``support``'s surfaces
    (footprint within ``margin`` of the surface's extent either way round, height under
    its clearance)."""
    limits = []
    for surface in surfaces_of(support):
        extent = np.sort(surface.polygon.max(0) - surface.polygon.min(0))
        limits.append((extent * margin, surface.clearance))

    def fits(sizes: np.ndarray) -> np.ndarray:
        sizes = np.asarray(sizes, float)
        foot = np.sort(sizes[:, :2], axis=1)
        ok = np.zeros(len(sizes), bool)
        for extent, clearance in limits:
            ok |= (foot <= extent).all(1) & (sizes[:, 2] <= clearance)
        return ok

    return fits


def no_room_on(asset: Asset, support: Asset) -> str | None:
    """Why ``asset`` can rest on none of ``support``'s surfaces, whatever its pose, or
    None: its contact rectangle (what touches the surface) is longer than every
    surface's diagonal, or its short side longer than every surface's long side. (A
    necessary test only: what passes may still find no place.)"""
    contact = np.sort(np.ptp(contact_rectangle(asset), axis=0))  # (short, long)
    best = None
    for surface in surfaces_of(support):
        extent = np.sort(np.ptp(surface.polygon, axis=0))
        if contact[1] <= np.hypot(*extent) and contact[0] <= extent[1]:
            return None
        if best is None or extent.prod() > best.prod():
            best = extent
    if best is None:
        return "nothing to rest on"
    return (f"too large: its base is {contact[1]:.2f} x {contact[0]:.2f} m, the largest "
            f"surface {best[1]:.2f} x {best[0]:.2f} m")  # fmt: skip


def placement_order(hierarchy: Hierarchy, assets: dict[str, Asset]) -> list:
    """The hierarchy's sequence with each support's dependents placed largest footprint
    first (the packing order that leaves room for the small ones), anchors still before
    their dependents: a topological order by (the support's turn, -footprint, sequence).
    Curtains and blinds hang first of all: they go where the windows are, and the
    furniture then stands around them rather than in front of the window they need.
    Among the other wall objects, those with a functional anchor hang before those
    without: a painting over the sofa has one stretch of wall, a mirror of no anchor any
    free one (a mirror hung first over a sofa left its painting nowhere to go)."""
    import heapq

    sequence = hierarchy.sequence()
    turn: dict[str, int] = {}
    for item in sequence:
        turn.setdefault(item.support, len(turn))
    waiting: dict[str, list[int]] = {}
    blockers = []
    for i, item in enumerate(sequence):
        deps = {item.support, item.functional} - {None, FLOOR}
        deps = {d for d in deps if d in assets}
        blockers.append(len(deps))
        for d in deps:
            waiting.setdefault(d, []).append(i)

    def key(i: int) -> tuple:
        item = sequence[i]
        size = assets[item.dependent.id].size
        hangs = on_wall(item.support)
        first = hangs and item.dependent.category in WINDOW_DRESSINGS
        free = hangs and not first and item.functional is None  # (any free stretch will do)
        return (-1 if first else turn[item.support], free, -float(size[0] * size[1]), i)

    heap = [key(i) for i in range(len(sequence)) if blockers[i] == 0]
    heapq.heapify(heap)
    out = []
    while heap:
        i = heapq.heappop(heap)[-1]
        out.append(sequence[i])
        for j in waiting.get(sequence[i].dependent.id, []):
            blockers[j] -= 1
            if blockers[j] == 0:
                heapq.heappush(heap, key(j))
    return out
