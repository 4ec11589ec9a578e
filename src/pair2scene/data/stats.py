"""Counts over a corpus: what ``pair2scene data stats`` prints."""

from __future__ import annotations

from collections import Counter

from pair2scene.categories import super_category
from pair2scene.data.base import Corpus
from pair2scene.scene.model import FLOOR


def corpus_stats(corpus: Corpus, split: str | None = None) -> dict:
    """Rooms, objects, per-category counts, support edges and what the adapter reported."""
    categories: Counter[str] = Counter()
    supers: Counter[str] = Counter()
    room_types: Counter[str] = Counter()
    splits: Counter[str] = Counter()
    edges = on_floor = unknown_support = 0
    for scene in corpus.scenes:
        room_types[scene.room.type] += 1
        splits[scene.split or "none"] += 1
        for o in scene.objects:
            categories[o.category] += 1
            supers[super_category(o.category).value] += 1
            if o.support == FLOOR:
                on_floor += 1
            elif o.support is None:
                unknown_support += 1
            else:
                edges += 1
    rep = corpus.report
    return {
        "source": corpus.source,
        "split": split or "all",
        "rooms": len(corpus.scenes),
        "objects": sum(categories.values()),
        "categories": dict(sorted(categories.items(), key=lambda kv: (-kv[1], kv[0]))),
        "super_categories": dict(sorted(supers.items())),
        "support_edges": edges,
        "floor_supported": on_floor,
        "support_unknown": unknown_support,
        "room_types": dict(sorted(room_types.items())),
        "splits": dict(sorted(splits.items())),
        "labels": {
            "mapped": len(rep.mapped_labels),
            "unknown": len(rep.unknown_labels),
            "unknown_objects": sum(rep.unknown_labels.values()),
        },
        "unknown_labels": dict(rep.unknown_labels.most_common()),
        "room_features": dict(rep.room_features.most_common()),
        "warnings": dict(rep.warnings.most_common()),
    }


def format_stats(stats: dict) -> str:
    """A human-readable summary of :func:`corpus_stats`."""
    lines = [
        f"source      {stats['source']} ({stats['split']})",
        f"rooms       {stats['rooms']}  "
        + ", ".join(f"{k} {v}" for k, v in stats["room_types"].items()),
        "splits      " + ", ".join(f"{k} {v}" for k, v in stats["splits"].items()),
        f"objects     {stats['objects']}  "
        + ", ".join(f"{k} {v}" for k, v in stats["super_categories"].items()),
        f"support     {stats['support_edges']} on objects, {stats['floor_supported']} on the "
        f"floor, {stats['support_unknown']} unknown",
        f"labels      {stats['labels']['mapped']} mapped, {stats['labels']['unknown']} unknown "
        f"({stats['labels']['unknown_objects']} objects kept as 'unknown')",
        f"categories  {len(stats['categories'])}: "
        + ", ".join(f"{k} {v}" for k, v in list(stats["categories"].items())[:12])
        + (" ..." if len(stats["categories"]) > 12 else ""),
    ]
    for key in ("unknown_labels", "room_features", "warnings"):
        if stats[key]:
            lines.append(
                f"{key.replace('_', ' '):<11} "
                + ", ".join(f"{k}: {v}" for k, v in stats[key].items())
            )
    return "\n".join(lines)
