"""ProcTHOR adapter: the three-house fixture and the shared ProcTHOR-1k files."""

import gzip
import json
from collections import Counter

import numpy as np
import pytest

from pair2scene.data.procthor import load_procthor
from pair2scene.errors import UserError
from pair2scene.scene.model import FLOOR


@pytest.fixture(scope="module")
def small(fixtures):
    return load_procthor(fixtures / "procthor" / "train.jsonl.gz", databases=fixtures / "ai2thor")


def test_one_scene_per_room(small):
    assert [s.id for s in small.scenes] == [
        "procthor/train/0/room|2",
        "procthor/train/1/room|2",
        "procthor/train/2/room|2",
    ]
    assert all(s.split == "train" and s.source == "procthor" for s in small.scenes)
    assert not small.report.warnings


def test_first_house(small):
    s = small.scenes[0]
    assert s.room.type == "living_room"
    assert s.room.area == pytest.approx(7.334**2, rel=1e-6)
    assert s.room.height == pytest.approx(2.9745535, abs=1e-6)
    assert len(s.room.doors) == 1 and len(s.room.windows) == 2
    door = s.room.doors[0]
    assert door.width == pytest.approx(4.9141008 - 3.8715087, abs=1e-6)
    assert door.z_min == 0.0 and door.z_max == pytest.approx(2.1035881, abs=1e-6)
    assert door.p0[1] == pytest.approx(7.33)  # the wall along y = 7.33
    tv_stand = s.get("tv_stand_0")
    assert tv_stand.support == FLOOR and tv_stand.box.bottom == pytest.approx(0.0, abs=1e-3)
    tv = s.get("television_0")
    assert tv.source_support == "tv_stand_0"
    assert tv.box.bottom == pytest.approx(tv_stand.box.top, abs=1e-3)  # resting in contact
    paintings = [o for o in s.objects if o.category == "painting"]
    assert paintings and all(p.support is None for p in paintings)


def test_nested_children_rest_on_their_parent(small):
    for s in small.scenes:
        objs = s.by_id()
        for o in s.objects:
            if o.support not in (None, FLOOR):
                gap = o.box.bottom - objs[o.support].box.top
                # ProcTHOR puts items on top surfaces or inside shelves of their parent
                assert gap > -objs[o.support].box.size[2], (s.id, o.id, gap)


@pytest.mark.shared_data
def test_shared_procthor_counts(procthor_1k):
    train = load_procthor(procthor_1k / "train.jsonl.gz")
    val = load_procthor(procthor_1k / "val.jsonl.gz")
    assert len(train.scenes) == 500 and len(val.scenes) == 100
    assert Counter(s.room.type for s in train.scenes + val.scenes).keys() == {
        "living_room",
        "bedroom",
        "kitchen",
    }
    assert not train.report.unknown_labels
    n = np.mean([len(s.objects) for s in train.scenes])
    assert 15 < n < 35  # "~23 objects each"


def test_folder_and_split_filter(fixtures):
    # the fixture folder holds train.jsonl.gz (3 houses) and val.jsonl.gz (4 houses)
    folder = fixtures / "procthor"
    both = load_procthor(folder, split="val", databases=fixtures / "ai2thor")
    assert len(both.scenes) == 4 and {s.split for s in both.scenes} == {"val"}
    assert {s.id.split("/")[2] for s in both.scenes} == {"0", "1", "2", "3"}
    everything = load_procthor(folder, databases=fixtures / "ai2thor")
    assert len(everything.scenes) == 7


@pytest.mark.parametrize(
    "content, needle",
    [
        (b"{not json\n", "line 1: not valid JSON"),
        (b"[1, 2]\n", "must be a JSON object"),
        (b'{"rooms": [{"floorPolygon": [{"x": 0}]}]}\n', "malformed house"),
    ],
)
def test_malformed_houses_give_one_line(tmp_path, fixtures, content, needle):
    f = tmp_path / "bad.jsonl.gz"
    f.write_bytes(gzip.compress(content))
    with pytest.raises(UserError, match=needle) as e:
        load_procthor(f, databases=fixtures / "ai2thor")
    assert "\n" not in str(e.value)


def test_not_gzip(tmp_path, fixtures):
    f = tmp_path / "x.jsonl.gz"
    f.write_text(json.dumps({"rooms": []}))
    with pytest.raises(UserError, match="not a readable"):
        load_procthor(f, databases=fixtures / "ai2thor")
