"""Objects on supports where and how the training rooms' stood: what the statistics learn
of each (dependent, support) pair, the test a candidate must pass, and a television kept
centred on its stand, facing its way."""

from __future__ import annotations

import numpy as np
import pytest

from pair2scene.assembly import anchors
from pair2scene.assembly.anchors import ALIGNED_MIN, MAX_OVERHANG, SpotGeometry, SpotRules
from pair2scene.assembly.place import AssemblyConfig, Placer
from pair2scene.assembly.sizes import SizeTable
from pair2scene.assets.identity import asset_seed
from pair2scene.assets.registry import generate
from pair2scene.assets.surfaces import surfaces_of
from pair2scene.curation.stats import HierarchyStats, aligned, parallel
from pair2scene.errors import UserError
from pair2scene.hierarchy.tree import Hierarchy
from pair2scene.scene.geometry import OrientedBox
from pair2scene.scene.model import FLOOR, Opening, Room, Scene, SceneObject

ROOM = Room(
    "living_room",
    np.array([[0, 0], [6, 0], [6, 5], [0, 5]], float),
    2.6,
    (Opening("door", (0.5, 0.0), (1.4, 0.0), 0.0, 2.1),),
)
STAND_SIZE = (1.6, 0.45, 0.55)
STAND = OrientedBox.from_yaw([3.0, 4.7, 0.275], STAND_SIZE, np.pi)
"""A TV stand against the north wall, facing south (-y)."""
TV_SIZE = (1.0, 0.25, 0.65)


def _on_stand(u: float, v: float = 0.0, turn: float = 0.0, size=TV_SIZE,
              stand: OrientedBox = STAND) -> OrientedBox:  # fmt: skip
    """A box resting on the stand at (u, v) of its canonical frame, turned ``turn`` from
    the stand's yaw."""
    local = np.array([u * stand.size[0] / 2, v * stand.size[1] / 2, 0.0])
    center = stand.center + stand.rotation @ local
    center[2] = stand.top + size[2] / 2
    return OrientedBox.from_yaw(center, size, stand.yaw + turn)


def _room(i: int, turned: bool = False) -> Scene:
    """A stand with a centred television facing its way (``turned``: backwards) and a vase
    at one end, a different end each room."""
    tv = _on_stand(0.0, 0.02 * (i % 3), np.pi if turned else 0.0)
    vase = _on_stand(0.8 if i % 2 else -0.8, 0.1, 0.3 * i, size=(0.15, 0.15, 0.3))
    return Scene(f"s{i}", ROOM, [
        SceneObject("stand", "tv_stand", STAND, None, FLOOR),
        SceneObject("tv", "television", tv, None, "stand"),
        SceneObject("vase", "vase", vase, None, "stand"),
    ])  # fmt: skip


def test_aligned_wraps_yaws():
    assert aligned(0.0) and aligned(np.radians(40)) and aligned(2 * np.pi - 0.1)
    assert not aligned(np.radians(50)) and not aligned(np.pi) and not aligned(-np.pi / 2)


def test_statistics_learn_how_and_where_dependents_stand_on_their_support():
    scenes = [_room(i, turned=i == 0) for i in range(8)]
    stats = HierarchyStats.fit(scenes)
    n, facing, su, suu, sv, svv, sw, sww, lying = stats.sup_geometry["television"]["tv_stand"]
    assert (n, facing, lying) == (8, 7, 8)  # one of the 8 turned backwards: still parallel
    assert su == pytest.approx(0.0, abs=1e-9) and suu == pytest.approx(0.0, abs=1e-9)
    assert sv / n == pytest.approx(0.02 * sum(i % 3 for i in range(8)) / 8)
    assert sw / n == pytest.approx(1.0 / 1.6)  # as wide as 5/8 of the stand
    assert stats.sup_geometry["vase"]["tv_stand"][2] == pytest.approx(0.0)  # both ends
    assert stats.sup_geometry["vase"]["tv_stand"][3] == pytest.approx(8 * 0.64)
    back = HierarchyStats.from_json(stats.to_json())
    assert back.sup_geometry["television"]["tv_stand"] == pytest.approx(
        stats.sup_geometry["television"]["tv_stand"], abs=1e-5
    )
    merged = HierarchyStats.merge([HierarchyStats.fit(scenes[:3]), HierarchyStats.fit(scenes[3:])])
    assert merged.sup_geometry["television"]["tv_stand"] == pytest.approx(
        stats.sup_geometry["television"]["tv_stand"]
    )


def test_statistics_with_malformed_sums_are_refused():
    doc = HierarchyStats.fit([_room(0)]).to_dict()
    doc["sup_geometry"]["television"]["tv_stand"] = [1, 1, 0, 0, 0, 0]  # 6 of 8 sums
    with pytest.raises(UserError, match="sup_geometry of television"):
        HierarchyStats.from_dict(doc)
    del doc["sup_geometry"]  # statistics written before it: no rule, still loaded
    assert HierarchyStats.from_dict(doc).sup_geometry == {}


def _rules(rooms: int = 40) -> SpotRules:
    """Rules from ``rooms`` rooms, the first with its television turned backwards."""
    return SpotRules.from_stats(HierarchyStats.fit([_room(i, i == 0) for i in range(rooms)]))


def test_rules_need_enough_pairs_and_hold_only_clear_preferences():
    assert _rules(4).rule("television", "tv_stand") is None  # 4 pairs: too few to say
    rules = _rules()
    rule = rules.rule("television", "tv_stand")
    assert rule.n == 40 and rule.aligned == pytest.approx(39 / 40)
    lo, hi = rule.window("u")
    assert lo == pytest.approx(-0.1) and hi == pytest.approx(0.1)  # no spread: the margin
    vase = rules.rule("vase", "tv_stand")
    assert vase.window("u")[1] > 1.0  # at either end: anywhere along the stand
    # the facing draw: a vase faces any way (a share far under ALIGNED_MIN), a TV 39 in 40
    assert vase.aligned < ALIGNED_MIN <= rule.aligned
    assert not any(rules.check("vase", "tv_stand", STAND, s).must_align for s in range(50))
    must = [rules.check("television", "tv_stand", STAND, s).must_align for s in range(2000)]
    assert np.mean(must) == pytest.approx(39 / 40, abs=0.015)
    assert rules.check("television", "dresser", STAND, 0) is None
    # 7 televisions in 8 facing their stand's way is not a rule: any way the model draws
    loose = _rules(8)
    assert not any(loose.check("television", "tv_stand", STAND, s).must_align for s in range(50))


def test_the_check_rejects_a_turned_or_off_centre_television_and_moves_it_back():
    check = _rules().check("television", "tv_stand", STAND, 0)
    check = type(check)(check.support, True, check.u, check.v)  # must face the stand's way
    assert check.reason(_on_stand(0.05, 0.1)) is None
    assert check.reason(_on_stand(0.0, 0.0, np.pi)) == "turned"
    assert check.reason(_on_stand(0.0, 0.0, np.pi / 2)) == "turned"
    assert check.reason(_on_stand(0.4)) == "off_spot"
    moved = check.onto(_on_stand(0.4, 0.0, 0.2))
    assert check.reason(moved) is None
    local = moved.in_frame_of(STAND)
    assert local.center[0] == pytest.approx(check.u[1], abs=1e-5)
    assert moved.center[2] == pytest.approx(_on_stand(0.4).center[2])  # height kept
    assert moved.yaw == pytest.approx(STAND.yaw + 0.2 - 2 * np.pi)  # and yaw


def test_overhang_is_one_spread_beyond_the_mean_ratio_and_capped():
    assert SpotGeometry(10, 1.0, (0, 0), (0, 0), (1.0, 0.1)).overhang == pytest.approx(1.1)
    assert SpotGeometry(10, 1.0, (0, 0), (0, 0), (1.1, 0.3)).overhang == MAX_OVERHANG
    assert SpotGeometry(10, 1.0, (0, 0), (0, 0)).overhang == 0.0  # no ratio known


class _Stand:
    """A stand-in model: the stand where given; a television's candidates on it, the first
    ``off`` of them at u = 0.6, the next ``turned`` facing backwards, the rest centred
    (``off`` None: every one at u = 0.6)."""

    honours_temperature = False
    draws_in_frames = True

    def __init__(self, off: int | None, turned: int = 0):
        self.off, self.turned = off, turned

    def draw(self, query, n, temperature, generator):
        if query.category == "tv_stand":
            return np.repeat(STAND.to_vector()[None], n, axis=0), None
        stand = query.support.box  # where placement put it (flush against the wall)
        out = np.repeat(_on_stand(0.0, 0.0, 0.0, query.size, stand).to_vector()[None], n, axis=0)
        off = _on_stand(0.6, 0.0, 0.0, query.size, stand).to_vector()
        if self.off is None:
            out[:] = off
            return out, None
        out[: self.off] = off
        turned = _on_stand(0.0, 0.0, np.pi, query.size, stand).to_vector()
        out[self.off : self.off + self.turned] = turned
        return out, None


def _tv_on_stand():
    h = Hierarchy("living_room")
    stand = h.add("tv_stand", FLOOR)
    tv = h.add("television", stand.id)
    h = h.validate()
    assets = {stand.id: generate("tv_stand", STAND_SIZE, 1, style=0),
              tv.id: generate("television", TV_SIZE, 2, style=0)}  # fmt: skip
    return h, assets


def _config(**kw) -> AssemblyConfig:
    return AssemblyConfig(walls=False, navigable=False, candidates=8, batches=2, **kw)


def _tv(result) -> OrientedBox:
    """The television in the frame of its stand."""
    boxes = {o.category: o.box for o in result.scene.objects}
    return boxes["television"].in_frame_of(boxes["tv_stand"])


def test_placement_keeps_a_television_centred_on_its_stand_facing_its_way(monkeypatch):
    monkeypatch.setattr(anchors, "PIN_STD", 0.0)  # the window alone, not the pinned spot
    h, assets = _tv_on_stand()
    rules = _rules()
    seed = next(s for s in range(50) if rules.check("television", "tv_stand", STAND,
                                                    _tv_seed(h, s)).must_align)  # fmt: skip
    placer = Placer(_Stand(off=5, turned=3), config=_config(), spots=rules)
    result = placer.place(h, ROOM, seed=seed, assets=assets)
    assert result.stats.placed == 2
    local = _tv(result)
    assert abs(local.center[0]) < 0.01 and aligned(local.yaw)
    assert result.stats.rejections == {"off_spot": 5, "turned": 3}

    loose = Placer(placer.model, config=_config(spots=False), spots=rules)
    local = _tv(loose.place(h, ROOM, seed=seed, assets=assets))
    assert local.center[0] == pytest.approx(0.6, abs=0.01)  # the first candidate, as drawn


def test_a_television_drawn_only_off_its_spot_is_moved_onto_it(monkeypatch):
    monkeypatch.setattr(anchors, "PIN_STD", 0.0)
    h, assets = _tv_on_stand()
    placer = Placer(_Stand(off=None), config=_config(), spots=_rules())
    result = placer.place(h, ROOM, seed=0, assets=assets)
    assert result.stats.placed == 2 and not result.stats.dropped
    u = _tv(result).center[0]
    assert u == pytest.approx(_rules().rule("television", "tv_stand").window("u")[1], abs=0.01)
    assert result.stats.rejections == {"off_spot": 16}


def test_a_pair_that_stood_at_one_spot_is_pinned_there():
    rules = _rules()  # 40 televisions all centred along the stand (u spread 0)
    check = rules.check("television", "tv_stand", STAND, 0)
    assert check.pin[0] == pytest.approx(0.0, abs=1e-9)
    assert check.pin[1] == pytest.approx(0.02 * sum(i % 3 for i in range(40)) / 40)
    moved = check.pinned(_on_stand(0.4, 0.3, 0.2))
    local = moved.in_frame_of(STAND)
    assert local.center[:2] == pytest.approx(check.pin, abs=1e-6)
    assert moved.center[2] == pytest.approx(_on_stand(0.4).center[2])  # height kept
    assert moved.yaw == pytest.approx(STAND.yaw + 0.2 - 2 * np.pi)  # and yaw
    vase = rules.check("vase", "tv_stand", STAND, 0)  # at either end, always at v = 0.1
    assert vase.pin[0] is None and vase.pin[1] == pytest.approx(0.1)
    local = vase.pinned(_on_stand(0.8, 0.3)).in_frame_of(STAND)
    assert local.center[:2] == pytest.approx([0.8, 0.1], abs=1e-6)
    assert _rules(12).check("television", "tv_stand", STAND, 0).pin == (None, None)  # < 20
    # placement: every candidate drawn off-centre, the first one moved onto the spot
    h, assets = _tv_on_stand()
    result = Placer(_Stand(off=None), config=_config(), spots=rules).place(
        h, ROOM, seed=0, assets=assets
    )
    assert result.stats.placed == 2 and result.stats.rejections == {}
    assert _tv(result).center[0] == pytest.approx(0.0, abs=1e-6)


def _tv_seed(h: Hierarchy, seed: int) -> int:
    tv = next(n for n in h.nodes if n.category == "television")
    return asset_seed(tv.id, seed)


def test_a_television_may_be_drawn_as_wide_as_the_training_rooms_stands_carried():
    """Sizes of objects on a support must fit one of its surfaces: within 0.9 of it, or
    the pair's overhang where the training rooms' were wider (televisions against their
    stands); never so wide that the support cannot carry it."""
    h, assets = _tv_on_stand()
    stand = {k: a for k, a in assets.items() if a.category == "tv_stand"}
    widths = np.linspace(0.8, 1.9, 12)
    sizes = SizeTable({"television": np.array([[w, 0.2, 0.6] for w in widths])})
    rules = _rules()
    wide = SpotRules(
        {"television": {"tv_stand": SpotGeometry(50, 1.0, (0, 0), (0, 0), (1.1, 0.2))}}
    )
    top = max(np.ptp(s.polygon[:, 0]) for s in surfaces_of(stand["tv_stand_0"]))

    def drawn(rules_, **kw):
        placer = Placer(_Stand(off=0), sizes, _config(**kw), spots=rules_)
        return [placer.assets_for(h, s, stand)["television_0"].size[0] for s in range(40)]

    narrow = drawn(rules)  # this pair's TVs were 0.62 of the stand: no overhang
    assert max(narrow) <= 0.9 * top * 1.2  # (sizes are jittered a few per cent)
    allowed = drawn(wide)
    assert max(allowed) > 0.9 * top * 1.1 and max(allowed) <= 1.2 * top * 1.2
    assert max(drawn(wide, spots=False)) == pytest.approx(max(narrow))  # switched off


def test_parallel_wraps_yaws_both_ways():
    assert parallel(0.0) and parallel(np.pi) and parallel(np.radians(220)) and parallel(-3.0)
    assert not parallel(np.pi / 2) and not parallel(np.radians(-100)) and not parallel(0.9)


REMOTE_SIZE = (0.06, 0.2, 0.02)


def _remotes(i: int) -> Scene:
    """A remote control on the stand, one way or the reverse in turn (so it faces the
    stand's way half the time), crosswise in every tenth room, along the stand anywhere."""
    turn = np.pi / 2 if i % 10 == 9 else np.pi * (i % 2)
    remote = _on_stand(-0.8 + 1.6 * (i % 7) / 6, 0.0, turn, size=REMOTE_SIZE)
    return Scene(f"r{i}", ROOM, [
        SceneObject("stand", "tv_stand", STAND, None, FLOOR),
        SceneObject("remote", "remote_control", remote, None, "stand"),
    ])  # fmt: skip


def test_a_pair_lying_one_way_draws_each_object_parallel_or_crosswise():
    stats = HierarchyStats.fit([_remotes(i) for i in range(40)])
    rules = SpotRules.from_stats(stats)
    rule = rules.rule("remote_control", "tv_stand")
    assert rule.parallel == pytest.approx(36 / 40) and rule.holds_parallel
    assert rule.aligned < ALIGNED_MIN  # facing either way: no "turned" rule
    lies = [rules.check("remote_control", "tv_stand", STAND, s, REMOTE_SIZE).parallel
            for s in range(2000)]  # fmt: skip
    assert np.mean(lies) == pytest.approx(0.9, abs=0.02)
    check = next(rules.check("remote_control", "tv_stand", STAND, s, REMOTE_SIZE)
                 for s in range(50) if lies[s])  # fmt: skip
    assert check.reason(_on_stand(0.2, 0.0, np.pi, REMOTE_SIZE)) is None
    assert check.reason(_on_stand(0.2, 0.0, np.pi / 2, REMOTE_SIZE)) == "crosswise"
    # a round object looks the same either way, and without its size none is held
    assert rules.check("remote_control", "tv_stand", STAND, 0, (0.1, 0.1, 0.1)).parallel is None
    assert rules.check("remote_control", "tv_stand", STAND, 0).parallel is None
    assert not _rules(8).rule("vase", "tv_stand").holds_parallel  # too few pairs
    # statistics written before the ninth sum load, and hold nothing
    doc = stats.to_dict()
    doc["sup_geometry"]["remote_control"]["tv_stand"] = doc["sup_geometry"]["remote_control"][
        "tv_stand"][:8]  # fmt: skip
    old = SpotRules.from_stats(HierarchyStats.from_dict(doc))
    assert old.rule("remote_control", "tv_stand").parallel is None
    assert old.check("remote_control", "tv_stand", STAND, 0, REMOTE_SIZE).parallel is None


class _Crosswise(_Stand):
    """Every candidate of the remote control lies across the stand."""

    def draw(self, query, n, temperature, generator):
        if query.category == "tv_stand":
            return np.repeat(STAND.to_vector()[None], n, axis=0), None
        box = _on_stand(0.0, 0.0, np.pi / 2, query.size, query.support.box)
        return np.repeat(box.to_vector()[None], n, axis=0), None


def test_an_object_drawn_only_the_other_way_is_still_placed():
    rules = SpotRules.from_stats(HierarchyStats.fit([_remotes(i) for i in range(40)]))
    h = Hierarchy("living_room")
    stand = h.add("tv_stand", FLOOR)
    remote = h.add("remote_control", stand.id)
    h = h.validate()
    assets = {stand.id: generate("tv_stand", STAND_SIZE, 1, style=0),
              remote.id: generate("remote_control", REMOTE_SIZE, 2)}  # fmt: skip
    size = assets[remote.id].size
    seed = next(s for s in range(50) if rules.check(
        "remote_control", "tv_stand", STAND, asset_seed(remote.id, s), size).parallel)  # fmt: skip
    placer = Placer(_Crosswise(off=0), config=_config(), spots=rules)
    result = placer.place(h, ROOM, seed=seed, assets=assets)
    assert result.stats.placed == 2 and not result.stats.dropped
    assert result.stats.rejections == {"crosswise": 16}  # then tried again either way
    boxes = {o.category: o.box for o in result.scene.objects}
    assert not parallel(boxes["remote_control"].in_frame_of(boxes["tv_stand"]).yaw)


class _CornerStand(_Stand):
    """:class:`_Stand` with the stand in the room's north-east corner, its east end flush
    against the east wall."""

    def draw(self, query, n, temperature, generator):
        if query.category == "tv_stand":
            corner = OrientedBox.from_yaw([6.0 - STAND_SIZE[0] / 2, 4.7, 0.275], STAND_SIZE,
                                          np.pi)  # fmt: skip
            return np.repeat(corner.to_vector()[None], n, axis=0), None
        return super().draw(query, n, temperature, generator)


def test_a_television_wider_than_its_stand_in_a_corner_is_drawn_narrower():
    """A television may overhang its stand's ends as the training rooms' did; where one
    end stands against a wall it cannot, and one drawn that wide is drawn again among the
    sizes that clear the wall centred (it had been dropped after every candidate reached
    through the wall). Mid-wall the wide ones stay."""
    h, assets = _tv_on_stand()
    stand = {k: a for k, a in assets.items() if a.category == "tv_stand"}
    sizes = SizeTable({"television": np.array([[w, 0.2, 0.6] for w in np.linspace(0.8, 1.9, 12)])})
    wide = SpotRules(
        {"television": {"tv_stand": SpotGeometry(50, 1.0, (0, 0), (0, 0), (1.1, 0.2))}}
    )
    widths = {}
    for name, model in (("corner", _CornerStand(off=0)), ("mid-wall", _Stand(off=0))):
        placer = Placer(model, sizes, _config(), spots=wide)
        widths[name] = []
        for seed in range(24):
            result = placer.place(h, ROOM, seed=seed, assets=placer.assets_for(h, seed, stand))
            assert not result.stats.dropped, (name, seed, result.stats.dropped)
            tv = next(o for o in result.scene.objects if o.category == "television")
            assert tv.box.corners()[:, 0].max() <= 6.0 + 1e-6
            widths[name].append(tv.box.size[0])
    assert max(widths["corner"]) <= STAND_SIZE[0] + 1e-6
    assert max(widths["mid-wall"]) > STAND_SIZE[0] + 0.1
    assert sum(w > STAND_SIZE[0] for w in widths["mid-wall"]) >= 4
