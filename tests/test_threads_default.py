"""Generation's torch threads: one per process unless asked (issue 22), same scenes."""

from __future__ import annotations

import pytest

torch = pytest.importorskip("torch")


def test_one_thread_unless_asked():
    from pair2scene.generate import set_threads

    before = torch.get_num_threads()
    try:
        set_threads()
        assert torch.get_num_threads() == 1
        set_threads(2)
        assert torch.get_num_threads() == 2
    finally:
        torch.set_num_threads(before)


def test_the_thread_count_does_not_change_a_scene():
    from pair2scene.generate import Pair2Scene, set_threads
    from pair2scene.io.scene_json import dumps_scene

    before = torch.get_num_threads()
    p2s = Pair2Scene.from_pretrained()
    try:
        texts = []
        for n in (1, 2):
            set_threads(n)
            texts.append(dumps_scene(p2s.generate(room="bedroom", seed=3).scene))
        assert texts[0] == texts[1]
    finally:
        torch.set_num_threads(before)
