"""One entry point for hierarchies: from a room type (statistics) or from text (LLM or
offline parser). The CLI's ``pair2scene hierarchy`` calls :func:`build_hierarchy`."""

from __future__ import annotations

from pathlib import Path

from pair2scene.curation.stats import HierarchyStats
from pair2scene.errors import UserError
from pair2scene.hierarchy.room_types import resolve
from pair2scene.hierarchy.synthesis import (
    HierarchyConfig,
    SynthesisConfig,
    load_stats,
    synthesize,
)
from pair2scene.hierarchy.tree import (
    HIERARCHY_FORMAT,
    HIERARCHY_VERSION,
    Hierarchy,
    HierarchyError,
)

LLM_CHOICES = ("auto", "never", "always")
"""``auto``: the LLM when an endpoint is configured, else the offline parser."""


def room_key(room: str) -> str:
    """'Living room' / 'living-room' / 'living_room' -> 'living_room'; apostrophes go and
    the aliases of composed room types (``resources/room_types.json``) are replaced by the
    type: "kids' room" / "children's room" -> 'kids_room', 'home office' -> 'office'."""
    return resolve(room)


def build_hierarchy(
    room: str | None = None,
    text: str | None = None,
    mode: str = "fit",
    max_objects: int | None = None,
    seed: int = 0,
    stats: HierarchyStats | str | Path | None = None,
    llm: str = "auto",
    config: HierarchyConfig | None = None,
) -> Hierarchy:
    """A validated hierarchy for ``room`` (a room type of the statistics) or ``text``;
    ``config``: the drawing settings (default :class:`HierarchyConfig`).

    Bounded whatever the request: ``max_objects`` above
    :data:`~pair2scene.hierarchy.synthesis.MAX_OBJECTS_LIMIT` is a UserError, a text is
    read up to :data:`~pair2scene.hierarchy.text.MAX_TEXT_CHARS` characters (by the LLM
    and the offline parser alike; a note says so) and its objects stop at the limit."""
    if (room is None) == (text is None):
        raise UserError("give exactly one of a room type or a text")
    if llm not in LLM_CHOICES:
        raise UserError(f"llm must be one of {', '.join(LLM_CHOICES)}")
    settings = config or HierarchyConfig()
    config = SynthesisConfig(mode=mode, max_objects=max_objects, seed=seed, k=settings.k,
                             beyond_load=settings.beyond_load,
                             template_anchors=settings.template_anchors)  # fmt: skip
    if not isinstance(stats, HierarchyStats):
        stats = load_stats(stats)
    if room is not None:
        return synthesize(stats, room_key(room), config)
    assert text is not None
    from pair2scene.hierarchy.text import limit_text, parse_text

    # One gate for both paths: an empty text or a negative count is refused, a long one cut.
    limited, notes = limit_text(text)
    if llm != "never":
        from pair2scene.hierarchy.llm import hierarchy_from_llm, llm_client_from_env

        client = llm_client_from_env()
        if client is not None:
            h = hierarchy_from_llm(client, limited, max_objects)
            h.notes[:0] = notes
            return h
        if llm == "always":
            raise UserError("--llm needs an endpoint: set PAIR2SCENE_LLM_BASE_URL (see README)")
    from pair2scene.hierarchy.from_text import hierarchy_from_spec

    return hierarchy_from_spec(parse_text(text), stats, config)  # (parse_text cuts, notes)


def read_hierarchy(path: str | Path) -> Hierarchy:
    """A hierarchy JSON (``pair2scene hierarchy --json``), validated; one-line errors."""
    from pair2scene.io.jsondoc import read_json_document

    doc = read_json_document(path, HIERARCHY_FORMAT, HIERARCHY_VERSION, "no such file")
    try:
        return Hierarchy.from_dict(doc, str(path))
    except HierarchyError as e:
        msg = str(e) if str(e).startswith(str(path)) else f"{path}: {e}"
        raise HierarchyError(msg) from None
