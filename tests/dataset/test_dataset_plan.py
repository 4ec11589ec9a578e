"""The dataset plan is a pure function of its settings; bad options end in one line."""

from __future__ import annotations

import pytest

from pair2scene.cli.dataset import run
from pair2scene.dataset.plan import (
    DatasetConfig,
    parse_formats,
    parse_mix,
    parse_slice,
    plan_scenes,
    plan_shards,
    room_counts,
    slice_shards,
)
from pair2scene.errors import UserError

MIX = (("bedroom", 0.4), ("kitchen", 0.3), ("living_room", 0.3))


def test_plan_is_deterministic_and_follows_the_mix():
    config = DatasetConfig(mix=MIX, num=25, shard_size=10, seed=7)
    first, second = plan_scenes(config), plan_scenes(config)
    assert first == second
    assert [s.seed for s in first] == list(range(7, 32))
    assert len({s.id for s in first}) == 25
    assert all(s.id == f"{s.room}_fit_{s.seed:08d}" for s in first)
    counts = {room: sum(s.room == room for s in first) for room, _ in MIX}
    assert counts == {"bedroom": 10, "kitchen": 8, "living_room": 7}
    # the rooms are blended, not in blocks
    assert len({s.room for s in first[:10]}) > 1
    shards = plan_shards(config)
    assert [len(s) for s in shards] == [10, 10, 5]
    assert [s for shard in shards for s in shard] == first
    # another seed, another order
    assert [s.room for s in plan_scenes(DatasetConfig(mix=MIX, num=25, seed=8))] != [
        s.room for s in first
    ]


def test_largest_remainder_counts_sum_to_num():
    for num in range(1, 40):
        counts = room_counts(MIX, num)
        assert sum(counts) == num
        assert all(abs(c - share * num) < 1 for c, (_, share) in zip(counts, MIX))


def test_mix_and_slices():
    assert parse_mix(None, ["Bedroom", "kitchen", "bedroom"]) == (
        ("bedroom", 0.5),
        ("kitchen", 0.5),
    )
    assert parse_mix("bedroom=2,kitchen=2", ["kitchen"]) == (("bedroom", 0.5), ("kitchen", 0.5))
    for bad in ("bedroom", "bedroom=x", "bedroom=-1", "bedroom=0", "bedroom=1,bedroom=2"):
        with pytest.raises(UserError):
            parse_mix(bad, [])
    with pytest.raises(UserError, match="not in --mix"):
        parse_mix("bedroom=1", ["kitchen"])
    assert parse_slice("1/3") == (1, 3)
    assert slice_shards(8, (1, 3)) == [1, 4, 7]
    assert sorted(i for k in range(3) for i in slice_shards(8, (k, 3))) == list(range(8))
    for bad in ("3/3", "a/b", "1", "-1/2", "0/0"):
        with pytest.raises(UserError):
            parse_slice(bad)
    assert parse_formats("png,json") == ("json", "png")


@pytest.mark.parametrize(
    "args, words",
    [
        (["--num", "0"], "--num"),
        (["--num", "4", "--jobs", "0"], "--jobs"),
        (["--num", "4", "--shard", "2/2"], "--shard"),
        (["--num", "4", "--mix", "bedroom=x"], "--mix"),
        (["--num", "4", "--executor", "spark"], "executor"),
        (["--num", "4", "--formats", "json,mjcf"], "--formats"),
        (["--num", "4", "--shard-format", "zip"], "shard format"),
        (["--num", "4", "--shard-size", "0"], "--shard-size"),
        (["--num", "4", "--mode", "dense"], "mode"),
        (["--num", "4", "--seed", str(2**32 - 2)], "--seed"),
        (["--num", "4", "--ray-address", "auto"], "--ray-address"),
        (["--num", "4", "--room", "spaceship"], "spaceship"),
        (["--num", "4", "--mix", "bedroom=1,garage=0"], "--mix: unknown room type 'garage'"),
        (["--num", "4", "--mix", "garage=1"], "--mix: unknown room type 'garage'"),
    ],
)
def test_bad_options_end_in_one_line(args, words, tmp_path, capsys):
    room = [] if "--room" in args or "--mix" in args else ["--room", "bedroom"]
    code = run([*room, "--out", str(tmp_path / "out"), *args])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("error: ") and words in err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("address", ["127.0.0.1:1", "ray://127.0.0.1:1", "[::1]:1"])
def test_an_address_nothing_answers_on_is_refused_at_once(address, tmp_path, capsys):
    pytest.importorskip("ray")
    out = tmp_path / "out"
    code = run(["--room", "bedroom", "--num", "2", "--executor", "ray", "--ray-address",
                address, "--out", str(out), "--quiet"])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "no Ray cluster answers there" in err
    assert not out.exists()
