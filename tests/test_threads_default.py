"""Generation's threads (issue 22): the layout model's forward passes run numpy's BLAS on
one thread whatever the machine or ``--threads`` (a BLAS rounds differently with its thread
count), the rest of the process's BLAS and torch get one thread unless asked, and the
scenes are the same bytes."""

from __future__ import annotations

from threadpoolctl import threadpool_info, threadpool_limits


def _blas_threads() -> set[int]:
    return {pool["num_threads"] for pool in threadpool_info() if pool["user_api"] == "blas"}


def test_the_forward_passes_run_on_one_blas_thread():
    from pair2scene.model.api import one_blas_thread

    with threadpool_limits(limits=2, user_api="blas"):
        with one_blas_thread():
            assert _blas_threads() in (set(), {1})
        assert _blas_threads() in (set(), {2})


def test_on_one_blas_thread_already_the_forward_pass_leaves_the_limits_alone():
    from pair2scene.model.api import one_blas_thread

    with threadpool_limits(limits=1, user_api="blas"):
        with one_blas_thread():
            assert _blas_threads() in (set(), {1})
        assert _blas_threads() in (set(), {1})


def test_floor_and_wall_clouds_are_made_once_read_only():
    import numpy as np

    from pair2scene.model.api import _frame_cloud
    from pair2scene.model.features import room_cloud, wall_cloud

    floor = _frame_cloud(True, (4.0, 3.0, 2.5), 256)
    assert floor is _frame_cloud(True, (4.0, 3.0, 2.5), 256) and not floor.flags.writeable
    assert floor.tobytes() == room_cloud((4.0, 3.0, 2.5), 256).tobytes()
    wall = _frame_cloud(False, (4.0, 0.2, 2.5), 256)
    assert wall.tobytes() == wall_cloud((4.0, 0.2, 2.5), 256).tobytes()
    assert not np.array_equal(wall, _frame_cloud(False, (3.0, 0.2, 2.5), 256))


def test_torch_gets_one_thread_unless_asked():
    import pytest

    torch = pytest.importorskip("torch")
    from pair2scene.generate import set_threads

    before = torch.get_num_threads()
    try:
        with threadpool_limits(limits=None):  # (put back the BLAS limits it sets)
            set_threads(2)
            assert torch.get_num_threads() == 2
            set_threads()
            assert torch.get_num_threads() == 1
    finally:
        torch.set_num_threads(before)


def test_every_blas_library_gets_one_thread_unless_asked():
    """numpy's and scipy's OpenBLAS each start a worker a core, which spin between the
    scene's small products outside the forward passes: two generating processes on two
    cores made 1.70x the scenes of one, 1.89x with one thread each."""
    import scipy.linalg  # noqa: F401  (loads scipy's own BLAS, as generation's imports do)

    from pair2scene.generate import set_threads

    with threadpool_limits(limits=2, user_api="blas"):
        assert _blas_threads() in (set(), {2})
        set_threads()
        assert _blas_threads() in (set(), {1})
        set_threads(2)
        assert _blas_threads() in (set(), {2})


def test_the_top_views_software_gl_gets_the_thread_count(monkeypatch):
    """Mesa's llvmpipe starts a rasterising thread a core unless LP_NUM_THREADS says;
    set_threads says, unless the environment had set it before pair2scene was imported."""
    import pair2scene.generate as generate

    monkeypatch.delenv("LP_NUM_THREADS", raising=False)
    with threadpool_limits(limits=None):  # (put back the BLAS limits it sets)
        monkeypatch.setattr(generate, "_USER_LP_THREADS", False)
        generate.set_threads()
        assert generate.os.environ["LP_NUM_THREADS"] == "1"
        generate.set_threads(2)
        assert generate.os.environ["LP_NUM_THREADS"] == "2"
        monkeypatch.setenv("LP_NUM_THREADS", "3")
        monkeypatch.setattr(generate, "_USER_LP_THREADS", True)
        generate.set_threads()
        assert generate.os.environ["LP_NUM_THREADS"] == "3"


def test_the_blas_threads_do_not_change_a_scene():
    from pair2scene.generate import Pair2Scene
    from pair2scene.io.scene_json import dumps_scene

    p2s = Pair2Scene.from_pretrained()
    texts = []
    for n in (1, 2):
        with threadpool_limits(limits=n, user_api="blas"):
            p2s.model._tokens.clear()  # (encode again, on this many threads around it)
            texts.append(dumps_scene(p2s.generate(room="bedroom", seed=3).scene))
    assert texts[0] == texts[1]
