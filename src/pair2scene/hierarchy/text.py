"""An offline, rule-based parser for natural-language room descriptions.

``parse_text("a bedroom with two nightstands and a lamp on each nightstand")`` gives a
:class:`TextSpec`: the room type, one :class:`Mention` per requested kind of object
(canonical category and count) and the :class:`Relation` s between them (support: rests
on; functional: placed relative to). It is deterministic and needs no network:

1. **tokens**: words, digits and punctuation, matched greedily against one lexicon, the
   longest phrase first ("coffee table" before "table", "floor lamp" before "floor"). The
   lexicon holds every canonical name and synonym of :mod:`pair2scene.categories` with
   English plurals, :data:`EXTRA_SYNONYMS`, :data:`GENERIC_NOUNS`, :data:`ROOM_WORDS` and
   the function-word tables below;
2. **elements**: noun phrases (determiner, count, modifiers, head noun, an optional
   "of ..." content), pronouns, relation cues, conjunctions, sentence breaks and seating
   phrases ("for eight");
3. **one pass** left to right: noun phrases become mentions (a definite or anchor phrase
   reuses the latest mention of its category), "with"-like cues open a list whose items
   relate to its head, "on"/"around"-like cues relate the trailing items of the current
   list to their anchor.

Walls and windows are room features, never mentions, but they say where things hang: "on
the wall" (and "wall-mounted", "mounted", "a wall mirror") puts a mention that can hang
(:data:`MOUNTABLE`: the wall objects, a TV, towel rails) on a wall, and a mention of
curtains or blinds related to windows hangs at them, one per window ("curtains on the
windows": two). Those mentions are listed in :attr:`TextSpec.on_wall`. The wall objects
and the fixtures things hang from, which the curated rooms always mount
(:data:`~pair2scene.curation.support.HANGER_CATEGORIES`: 58 of 58 towel rails, 22 of 22
toilet roll holders on a wall), hang on a wall without being told, unless the text puts
them on something.

Words that look like objects but are not understood go to :attr:`TextSpec.unparsed`.

Counts: "0 beds", "zero beds", "no beds", "without a TV" ask for none: nothing is
mentioned, and the category is listed in :attr:`TextSpec.excluded` so that nothing from
the statistics adds one either. A minus sign before a number ("-5 beds") is refused with
a one-line :class:`~pair2scene.errors.UserError` (a count must be a positive number);
a range "3-4 chairs" reads its first number.

Bounds: a description longer than :data:`MAX_TEXT_CHARS` is cut there (at the last word
break before it) with a note in :attr:`TextSpec.notes` (:func:`limit_text`; the LLM path
gets the same cut text and note through
:func:`pair2scene.hierarchy.build.build_hierarchy`).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import lru_cache
from typing import Any

from pair2scene.categories import BY_NAME, CATEGORIES, WINDOW_DRESSINGS, RoomType, SuperCategory
from pair2scene.curation.support import HANGER_CATEGORIES
from pair2scene.errors import UserError

SUPPORT = "support"
FUNCTIONAL = "functional"
RELATION_KINDS = (SUPPORT, FUNCTIONAL)


@dataclass(frozen=True)
class Mention:
    """One kind of object the text asks for."""

    ref: str
    """Unique id within the spec: ``m0``, ``m1``, ... in order of appearance."""
    category: str
    """Canonical category name; never a structure, part or unknown category."""
    count: int
    """How many the text asks for (>= 1); under an ``each`` relation, per anchor instance."""
    phrase: str
    """The words it came from, e.g. ``two nightstands``."""

    def __post_init__(self) -> None:
        if self.count < 1:
            raise ValueError(f"{self.ref}: count must be >= 1, not {self.count}")


@dataclass(frozen=True)
class Relation:
    """How one mention is placed with respect to another."""

    kind: str
    """``support``: the dependent rests on the anchor; ``functional``: the dependent is
    placed relative to the anchor (chairs around a table, a chair at a desk)."""
    dependent: str
    """The :attr:`Mention.ref` of the object being placed."""
    anchor: str
    """The :attr:`Mention.ref` of the object it is placed on or relative to."""
    each: bool
    """True: the dependent's count is per instance of the anchor ("a lamp on each
    nightstand"); False: the dependent's count is spread over the anchor's instances."""
    over: bool = False
    """A functional relation the text put "above" or "over" ("a painting above the
    sofa"): a dependent hung on a wall hangs over its anchor, within its width
    (:attr:`~pair2scene.hierarchy.tree.Hierarchy.over`)."""
    across: bool = False
    """A functional relation the text put "opposite", "across from" or "facing" ("a TV on
    the wall opposite the sofa"): a dependent hung on a wall hangs across the room from
    its anchor, where the anchor faces it
    (:attr:`~pair2scene.hierarchy.tree.Hierarchy.across`)."""

    def __post_init__(self) -> None:
        if self.kind not in RELATION_KINDS:
            raise ValueError(f"relation kind must be one of {RELATION_KINDS}, not {self.kind!r}")


@dataclass(frozen=True)
class TextSpec:
    """What :func:`parse_text` understood of a room description."""

    text: str
    """The description as given."""
    room_type: str | None
    """A :class:`~pair2scene.categories.RoomType` value when the text names a room
    (``other`` never); None when it names none."""
    mentions: tuple[Mention, ...]
    """The requested objects, in order of appearance."""
    relations: tuple[Relation, ...]
    """Support and functional relations between mentions: at most one of each kind per
    dependent, and never a cycle."""
    unparsed: tuple[str, ...]
    """Content words or phrases that were not understood (for a warning), e.g.
    ``("spaceship",)``."""
    on_wall: tuple[str, ...] = ()
    """The :attr:`Mention.ref` s the text hangs on a wall ("a mirror on the wall", "a
    wall-mounted TV", "curtains on the windows"), in order of appearance. A mention here
    has no support relation; it may have a functional one ("a TV on the wall opposite the
    sofa")."""
    mid_room: tuple[str, ...] = ()
    """The :attr:`Mention.ref` s of floor objects the text wants clear of every wall: "a
    kitchen island", "a table in the middle of the room" (:data:`MID_ROOM_NAMES`, a
    "middle" cue to the room)."""
    facing: tuple[str, ...] = ()
    """The :attr:`Mention.ref` s the text stands face to face ("two sofas facing each
    other": the mention's instances, the second and later facing the first; "a sofa and an
    armchair facing each other": the armchair, related to the sofa, faces it)."""
    excluded: tuple[str, ...] = ()
    """Categories the text asks for none of ("no desk", "0 beds", "without a TV"; a generic
    noun, "no lamps", every category it covers) and names nowhere else: the statistics add
    none of them."""
    notes: tuple[str, ...] = ()
    """What was done to the text before it was read (cut at :data:`MAX_TEXT_CHARS`)."""


# -- tables ---------------------------------------------------------------------------------

# Counts written as words.
# fmt: off
NUMBER_WORDS: dict[str, int] = {
    "one": 1, "two": 2, "three": 3, "four": 4, "five": 5, "six": 6, "seven": 7, "eight": 8,
    "nine": 9, "ten": 10, "eleven": 11, "twelve": 12, "thirteen": 13, "fourteen": 14,
    "fifteen": 15, "sixteen": 16, "seventeen": 17, "eighteen": 18, "nineteen": 19,
    "twenty": 20, "single": 1, "zero": 0,
}

# Vague quantities and the count they stand for.
QUANTITY_PHRASES: dict[str, int] = {
    "a pair of": 2, "pair of": 2, "a couple of": 2, "a couple": 2, "couple of": 2,
    "a few": 2, "few": 2, "some": 2, "several": 3, "multiple": 3, "a number of": 3,
    "many": 5, "lots of": 5, "a lot of": 5, "plenty of": 5, "loads of": 5, "a bunch of": 5,
    "a stack of": 5, "a pile of": 5, "a row of": 5, "a collection of": 5, "numerous": 5,
    "a dozen": 12, "dozen": 12, "dozens of": 12, "half a dozen": 6,
}
# fmt: on

PLURAL_COUNT = 2
"""The count of a bare plural ("chairs around the table")."""
FILL_COUNT = 5
"""The count of a bare plural that fills something ("a shelf full of books")."""
CONTENT_COUNT = 3
"""The count of a bare plural held by a container ("a bowl of fruit")."""
EACH_COUNT = 2
"""The count of a new mention introduced with each/every/both ("a lamp on each nightstand")."""

INDEF, DEF, EACH, BOTH, ANOTHER, NEG = "indef", "def", "each", "both", "another", "neg"
IT, THEM, ONE = "it", "them", "one"
RECIPROCAL = "each other"

# Determiners: INDEF a new object, DEF refers back, EACH/BOTH refer back per instance,
# ANOTHER always a new mention, NEG drops the phrase ("no tv").
# fmt: off
DETERMINERS: dict[str, str] = {
    "a": INDEF, "an": INDEF,
    "the": DEF, "this": DEF, "that": DEF, "these": DEF, "those": DEF, "its": DEF,
    "their": DEF, "my": DEF, "our": DEF, "your": DEF, "his": DEF, "her": DEF,
    "each": EACH, "every": EACH, "all": EACH, "all the": EACH, "all of the": EACH,
    "each of the": EACH, "every one of the": EACH,
    "both": BOTH, "both the": BOTH, "both of the": BOTH,
    "another": ANOTHER, "one more": ANOTHER, "more": ANOTHER, "an extra": ANOTHER,
    "extra": ANOTHER, "an additional": ANOTHER, "additional": ANOTHER, "a second": ANOTHER,
    "second": ANOTHER, "a third": ANOTHER, "third": ANOTHER,
    "no": NEG, "not": NEG, "not a": NEG, "not any": NEG,
}

# Pronouns: "it"/"them" refer to the furniture last talked about, EACH per instance.
PRONOUNS: dict[str, str] = {
    "it": IT, "them": THEM, "they": THEM, "each one": EACH, "each of them": EACH,
    "every one of them": EACH, "all of them": EACH, "both of them": EACH, "each of those": EACH,
    "each other": RECIPROCAL, "one another": RECIPROCAL,
}
# fmt: on

# Words joining list items; a comma additionally may close a nested "with" list.
CONJUNCTIONS = ("and", "or", "plus", "as well as", "along with", "together with", "but", "&")
COMMA = ","
# Punctuation ending a sentence: the next one starts a fresh list.
SENTENCE_BREAKS = (".", ";", "!", "?", ":")

# Rooms named in the text, as RoomType values. A room word is never an object.
_BED, _LIV, _KIT, _BATH = (
    RoomType.BEDROOM.value,
    RoomType.LIVING_ROOM.value,
    RoomType.KITCHEN.value,
    RoomType.BATHROOM.value,
)
_DIN, _OFF, _APT = RoomType.DINING_ROOM.value, RoomType.OFFICE.value, RoomType.APARTMENT.value
# composed room types (resources/room_types.json), not in RoomType: no training room has them
_STUDY, _KIDS = "study", "kids_room"
# fmt: off
ROOM_WORDS: dict[str, str] = {
    "bedroom": _BED, "bed room": _BED, "master bedroom": _BED, "guest bedroom": _BED,
    "guest room": _BED, "spare room": _BED, "kids room": _KIDS, "kid room": _KIDS,
    "childrens room": _KIDS, "children room": _KIDS, "nursery": _BED,
    "living room": _LIV, "livingroom": _LIV, "lounge": _LIV, "family room": _LIV,
    "sitting room": _LIV, "front room": _LIV, "tv room": _LIV, "den": _LIV,
    "kitchen": _KIT, "kitchenette": _KIT,
    "bathroom": _BATH, "bath room": _BATH, "restroom": _BATH, "washroom": _BATH,
    "powder room": _BATH, "shower room": _BATH, "ensuite": _BATH, "en suite": _BATH,
    "dining room": _DIN, "dining area": _DIN,
    "office": _OFF, "home office": _OFF, "study": _STUDY, "study room": _STUDY,
    "workspace": _OFF, "work space": _OFF, "workroom": _OFF, "library": _STUDY,
    "studio apartment": _APT, "studio": _APT, "apartment": _APT, "flat": _APT, "loft": _APT,
    "bedsit": _APT, "condo": _APT, "living dining room": _APT,
}

# Everyday names the category vocabulary lacks (category names are checked at import).
EXTRA_SYNONYMS: dict[str, str] = {
    "shelf": "shelving_unit", "wall shelf": "shelving_unit", "book shelf": "shelving_unit",
    "book case": "shelving_unit", "shelving": "shelving_unit",
    "telly": "television", "flatscreen": "television", "flat screen": "television",
    "tv set": "television",
    "sofa bed": "sofa", "sectional": "sofa", "futon": "sofa", "chaise longue": "sofa",
    "recliner": "armchair", "rocking chair": "armchair", "reading chair": "armchair",
    "wing chair": "armchair", "wingback chair": "armchair",
    "bench": "ottoman", "beanbag": "ottoman", "bean bag": "ottoman", "pouffe": "ottoman",
    "night table": "side_table", "bedside cabinet": "side_table", "lamp table": "side_table",
    "chest": "dresser",
    "kitchen island": "counter_top", "island": "counter_top", "worktop": "counter_top",
    "oven": "stove", "cooker": "stove",
    "freezer": "fridge", "fridge freezer": "fridge",
    "tv cabinet": "tv_stand", "tv console": "tv_stand", "media unit": "tv_stand",
    "entertainment center": "tv_stand", "entertainment unit": "tv_stand",
    "laptop computer": "laptop",
    "ceiling light": "ceiling_lamp", "pendant light": "ceiling_lamp",
    "light fixture": "ceiling_lamp", "wall light": "wall_lamp", "bedside lamp": "table_lamp",
    "bed frame": "bed", "crib": "bed", "cot": "bed",
    "towel rack": "towel_holder", "towel bar": "towel_holder",
    "houseplant": "house_plant", "flower pot": "house_plant", "flowerpot": "house_plant",
    "photo": "painting", "photograph": "painting", "wall art": "painting",
    "fruit": "apple", "fruit bowl": "bowl", "teapot": "kettle",
    "dustbin": "garbage_can", "trashcan": "garbage_can",
    "sink basin": "sink", "bathtub basin": "bathtub", "shower stall": "shower",
}
# fmt: on

IMPLIED_ANCHORS: dict[str, str] = {
    "nightstand": "bed",
    "night stand": "bed",
    "bedside table": "bed",
    "night table": "bed",
    "bedside cabinet": "bed",
    "dining chair": "dining_table",
    "desk chair": "desk",
    "office chair": "desk",
    "bar stool": "counter_top",
    "barstool": "counter_top",
    "counter stool": "counter_top",
}
"""Names that say what their object stands at: nightstands at a bed, bar stools at a
counter. A mention so named with no relation in the text takes the first mention of that
category as its functional anchor ("a double bed, two nightstands and a wardrobe": both
nightstands at the bed), else the room's object of it (:func:`implied_anchor`)."""

MID_ROOM_NAMES = ("island", "kitchen island", "centre island", "center island")
"""Names of furniture that stands clear of every wall (:attr:`TextSpec.mid_room`): an
island is the counter a kitchen's walls do not hold (a counter is otherwise built against
one, as 0.93 of the training rooms' were)."""

MASS_NOUNS = frozenset({"fruit"})
"""Singular forms that count like a bare plural ("a bowl of fruit")."""

PLURAL_FORM_NAMES = frozenset(
    {"curtains", "blinds", "drapes", "boots", "shoes", "keys", "tissues", "paper towels"}
)
"""Plural-looking names of one object: "curtains" is one curtains object."""

GENERIC_NOUNS: dict[str, tuple[str, ...]] = {
    "table": ("dining_table", "coffee_table", "side_table", "desk", "dressing_table"),
    "lamp": ("table_lamp", "floor_lamp", "wall_lamp", "ceiling_lamp"),
}
"""Nouns covering several categories: a reference ("the table") means the latest mentioned
of them, a new object the first one (or :data:`GENERIC_ROOM_DEFAULTS`)."""

GENERIC_ROOM_DEFAULTS: dict[tuple[str, str], str] = {("table", _BED): "side_table"}
"""A generic noun's new object in a given room type."""

CONTAINERS = frozenset(
    {
        "cabinet", "wardrobe", "dresser", "shelving_unit", "fridge", "box", "bowl", "sink",
        "bathtub", "garbage_can", "laundry_hamper", "cart", "tv_stand", "side_table", "desk",
        "dressing_table", "safe", "vase", "cup", "mug", "pot", "pan", "plate", "microwave",
    }
)  # fmt: skip
"""Categories that hold things "in" them ("plates in the cabinet", "a bowl of fruit")."""

SEAT_TARGETS: dict[str, str] = {"dining_table": "chair", "desk": "chair", "counter_top": "stool"}
"""What seats a table-like category ("a dining table for eight": eight chairs)."""
SEATING_ROOMS = frozenset({_DIN, _KIT, _APT, None})
"""Rooms where "for eight" means a dining table with eight chairs."""
# Phrases announcing a number of seats ("a table for six", "seats 4").
SEAT_CUES = ("for", "for up to", "seats", "seats up to", "seating", "seating for", "seat", "sits")
# Words that may follow the number of seats ("for eight people").
SEAT_PEOPLE = ("people", "persons", "person", "guests", "diners", "adults", "kids", "children")

WALL_OBJECTS = frozenset(c.name for c in CATEGORIES if c.super is SuperCategory.WALL_OBJECT)
"""Categories that always hang on a wall unless the text puts them on something ("a
painting above the sofa" hangs above it)."""
MOUNTABLE = WALL_OBJECTS | HANGER_CATEGORIES | {"television"}
"""Categories that hang on a wall when the text says so ("a TV on the wall"): the wall
objects, televisions and the fixtures the curated rooms mount (towel rails). Anything else
"on the wall" keeps its usual support (a shelf on the wall stands against it)."""
WALL_LAMP = "wall_lamp"
"""What the generic "lamp" becomes on a wall ("a lamp on the wall")."""
WALLS_PER_ROOM = 4
"""What "each wall" / "every wall" / "all the walls" counts (a rectangular room)."""
WINDOW, WALL = "window", "wall"
"""The room features (structure categories) that carry objects."""
# Words saying that the noun phrase they are in, or the one before them, hangs on a wall.
MOUNT_WORDS = ("mounted", "wall mounted", "wall hung")


@dataclass(frozen=True)
class _Cue:
    kind: str
    """support / functional, or with (by the dependent: small objects support, the rest
    functional), or negate ("without")."""
    head_first: bool = False
    """True: "HEAD with ITEMS"; False: "ITEMS on ANCHOR"."""
    each: bool = False
    """The items relate to each instance of the head ("each with")."""
    fill: bool = False
    """Bare plural items count :data:`FILL_COUNT` ("full of books")."""
    container: bool = False
    """Relates only when the anchor is one of :data:`CONTAINERS` ("in")."""
    pair: bool = False
    """One item per side: a single item becomes two ("a nightstand on either side of")."""
    over: bool = False
    """The items are above the anchor ("a painting above the sofa"): one hung on a wall
    hangs over it (:attr:`Relation.over`)."""
    across: bool = False
    """The items face the anchor from across the room ("a TV opposite the sofa"): one hung
    on a wall hangs where the anchor faces it (:attr:`Relation.across`)."""
    middle: bool = False
    """The items stand in the middle of the anchor: of the room, clear of its walls
    (:attr:`TextSpec.mid_room`); of an object, relative to it."""


WITH, NEGATE = "with", "negate"
_S, _F = _Cue(SUPPORT), _Cue(FUNCTIONAL)
_IN = _Cue(SUPPORT, container=True)
_PAIR = _Cue(FUNCTIONAL, pair=True)
_OVER = _Cue(FUNCTIONAL, over=True)
_ACROSS = _Cue(FUNCTIONAL, across=True)
_MID = _Cue(FUNCTIONAL, middle=True)
_W, _WS = _Cue(WITH, head_first=True), _Cue(SUPPORT, head_first=True)
_FILL, _WF = _Cue(SUPPORT, head_first=True, fill=True), _Cue(FUNCTIONAL, head_first=True)

# Cues "ITEMS <cue> ANCHOR": what the items before the cue are to the anchor after it.
# fmt: off
RELATION_CUES: dict[str, _Cue] = {
    "on": _S, "on top of": _S, "on top": _S, "onto": _S, "upon": _S, "atop": _S,
    "in": _IN, "inside": _IN, "inside of": _IN, "into": _IN, "within": _IN,
    "around": _F, "at": _F, "next to": _F, "beside": _F, "besides": _F, "by": _F, "near": _F,
    "close to": _F, "facing": _ACROSS, "opposite": _ACROSS, "opposite to": _ACROSS,
    "opposite of": _ACROSS, "across from": _ACROSS, "in front of": _F, "behind": _F,
    "under": _F, "underneath": _F, "beneath": _F, "below": _F, "above": _OVER, "over": _OVER,
    "alongside": _F, "along": _F,
    "against": _F, "between": _F, "flanking": _F, "surrounding": _F, "adjacent to": _F,
    "to the left of": _F, "to the right of": _F, "on the left of": _F, "on the right of": _F,
    "left of": _F, "right of": _F, "at the foot of": _F, "at the end of": _F,
    "at the head of": _F, "in the middle of": _MID, "in the center of": _MID,
    "in the centre of": _MID, "in the middle": _MID, "in the center": _MID,
    "in the centre": _MID, "pointing at": _F, "looking at": _F, "toward": _F, "towards": _F,
    "on either side of": _PAIR, "on each side of": _PAIR, "on both sides of": _PAIR,
    "either side of": _PAIR, "on either side": _PAIR, "on each side": _PAIR,
    "on both sides": _PAIR,
}

# Cues "HEAD <cue> ITEMS": the items after the cue relate to the head before it. Each
# also exists as "each <cue>" and "both <cue>" (per instance of the head).
HEAD_CUES: dict[str, _Cue] = {
    "with": _W, "has": _W, "have": _W, "having": _W, "had": _W, "contains": _W,
    "containing": _W, "contain": _W, "includes": _W, "including": _W, "include": _W,
    "featuring": _W, "features": _W, "feature": _W, "equipped with": _W,
    "furnished with": _W, "holding": _WS, "holds": _WS, "topped with": _WS,
    "full of": _FILL, "filled with": _FILL, "stocked with": _FILL, "lined with": _FILL,
    "covered with": _FILL, "covered in": _FILL, "packed with": _FILL, "loaded with": _FILL,
    "piled with": _FILL, "stacked with": _FILL,
    "surrounded by": _WF, "flanked by": _WF, "accompanied by": _WF,
    "without": _Cue(NEGATE, head_first=True), "except": _Cue(NEGATE, head_first=True),
}

# Adjectives and other words that may sit inside a noun phrase ("a large wooden table").
MODIFIERS = frozenset("""
    small large big little tiny huge giant long short tall low high wide narrow round square
    rectangular oval white black grey gray red blue green yellow brown beige pink purple
    orange dark light bright wooden wood metal leather fabric plastic marble oak pine walnut
    steel stone velvet wicker rattan ceramic porcelain modern contemporary vintage rustic
    minimalist classic traditional industrial scandinavian cozy cosy comfortable comfy
    elegant simple nice beautiful old new antique luxurious fancy stylish cute pretty plain
    matching soft hard double queen king twin sized size upholstered folding potted framed
    electric open empty spare main master guest l shaped unit very really quite coffee tea
    water wine milk juice dining reading
""".split())

# Words that are understood and carry nothing: verbs, fillers, places in a room.
IGNORED_WORDS = frozenset("""
    i im id we you me us want wants wanted need needs would like love please make create
    generate design build give show render imagine put place add set arrange there here is
    are was be being been should could can will must may might let lets get do does to also
    too just only which who where whose as so then sitting standing resting placed
    positioned located arranged hanging hung hang lying stacked tucked pushed stands
    rests hangs room rooms space area corner middle center centre side sides left right
    front back rear end top bottom edge spot furniture furnishings stuff things thing items
    item objects object scene layout setup up down out off away together nearby somewhere
    house home building work working sleeping eating relaxing cooking
""".split())
# fmt: on

# -- tokens ---------------------------------------------------------------------------------

NOUN, DET, NUM, CUE, PRON, CONJ, SEP, SEAT, PEOPLE, OF, MOD, SKIP, UNK, MOUNT = (
    "noun", "det", "num", "cue", "pron", "conj", "sep", "seat", "people", "of", "mod", "skip",
    "unk", "mount",
)  # fmt: skip
OBJECT, GENERIC, ROOM, FEATURE = "object", "generic", "room", "feature"

_TOKEN = re.compile(r"[^\W\d_]+(?:['’][^\W\d_]+)*|\d+|[,;.!?:&]")


@dataclass(frozen=True)
class _Noun:
    kind: str
    """OBJECT (a category), GENERIC (a :data:`GENERIC_NOUNS` word), ROOM (a RoomType
    value) or FEATURE (structure or part: understood, never an object)."""
    value: str
    plural: bool = False


@dataclass(frozen=True)
class _Tok:
    kind: str
    value: Any
    """A :class:`_Noun`, :class:`_Cue`, count, determiner or pronoun kind, or the word."""
    start: int
    end: int


def _words(text: str) -> list[tuple[str, int, int]]:
    """Lower-cased words, digits and punctuation with their spans; apostrophes dropped."""
    return [
        (m.group().lower().replace("'", "").replace("’", ""), m.start(), m.end())
        for m in _TOKEN.finditer(text)
    ]


def _key(phrase: str) -> tuple[str, ...]:
    """A table phrase as the words the tokenizer sees."""
    return tuple(w for w, _, _ in _words(phrase))


def _plurals(word: str) -> set[str]:
    """English plurals of one word (rules only; the lexicon has no irregular nouns)."""
    if word.endswith(("s", "x", "z", "ch", "sh")):
        return {word + "es"}
    if len(word) > 1 and word.endswith("y") and word[-2] not in "aeiou":
        return {word[:-1] + "ies"}
    if word.endswith("ife"):
        return {word[:-3] + "ives", word + "s"}
    if word.endswith("f") and not word.endswith("ff"):
        return {word[:-1] + "ves", word + "s"}
    if word.endswith("o"):
        return {word + "s", word + "es"}
    return {word + "s"}


def _plural_keys(key: tuple[str, ...]) -> set[tuple[str, ...]]:
    """Plural forms of a phrase: its last word, or the word before "of" ("chests of drawers")."""
    i = key.index("of", 1) - 1 if "of" in key[1:] else len(key) - 1
    if key[i].endswith("s") and not key[i].endswith("ss"):
        return set()
    return {key[:i] + (p,) + key[i + 1 :] for p in _plurals(key[i])}


def _nouns() -> dict[tuple[str, ...], _Noun]:
    """Every noun phrase the parser knows, singular and plural."""
    singular: dict[tuple[str, ...], _Noun] = {}
    for cat in CATEGORIES:
        kind = FEATURE if cat.super in (SuperCategory.STRUCTURE, SuperCategory.PART) else OBJECT
        for phrase in (cat.name, *cat.synonyms):
            singular[_key(phrase.replace("_", " "))] = _Noun(kind, cat.name)
    for phrase, name in EXTRA_SYNONYMS.items():
        singular[_key(phrase)] = _Noun(OBJECT, name, plural=phrase in MASS_NOUNS)
    for word in GENERIC_NOUNS:
        singular[_key(word)] = _Noun(GENERIC, word)
    for phrase, room in ROOM_WORDS.items():
        singular[_key(phrase)] = _Noun(ROOM, room)
    nouns = dict(singular)
    for key, noun in singular.items():
        for plural in _plural_keys(key):
            same = singular.get(plural)
            if same is None or (
                same.value == noun.value and " ".join(plural) not in PLURAL_FORM_NAMES
            ):
                nouns[plural] = _Noun(noun.kind, noun.value, plural=True)
    return nouns


@dataclass(frozen=True)
class _Lexicon:
    phrases: dict[tuple[str, ...], tuple[str, Any]]
    """Words -> token kind and value."""
    longest: int
    """The most words in one phrase."""
    noun_starts: frozenset[tuple[str, str]]
    """The first two words of every multi-word noun: a function phrase may not end inside
    one ("on each side" + "table" is "on each" + "side table")."""


@lru_cache(maxsize=1)
def _lexicon() -> _Lexicon:
    """Every phrase the tokenizer knows; function words win over nouns, nouns over
    modifiers and ignored words."""
    lex: dict[tuple[str, ...], tuple[str, Any]] = {}
    lex.update({(w,): (MOD, w) for w in MODIFIERS})
    lex.update({(w,): (SKIP, w) for w in IGNORED_WORDS})
    lex.update({(w,): (PEOPLE, w) for w in SEAT_PEOPLE})
    nouns = _nouns()
    lex.update({key: (NOUN, noun) for key, noun in nouns.items()})
    tables: list[tuple[str, dict[str, Any]]] = [
        (DET, dict(DETERMINERS)),
        (NUM, {**NUMBER_WORDS, **QUANTITY_PHRASES}),
        (PRON, dict(PRONOUNS)),
        (CONJ, {w: w for w in CONJUNCTIONS} | {COMMA: COMMA}),
        (SEP, {w: w for w in SENTENCE_BREAKS}),
        (SEAT, {w: w for w in SEAT_CUES}),
        (CUE, dict(RELATION_CUES)),
        (CUE, dict(HEAD_CUES)),
        (CUE, {f"{q} {p}": _Cue(c.kind, head_first=True, each=True, fill=c.fill)
               for p, c in HEAD_CUES.items() for q in ("each", "both") if c.kind != NEGATE}),
        (OF, {"of": "of"}),
        (MOUNT, {w: w for w in MOUNT_WORDS}),
    ]  # fmt: skip
    for kind, table in tables:
        lex.update({_key(phrase): (kind, value) for phrase, value in table.items()})
    starts = frozenset((key[0], key[1]) for key in nouns if len(key) > 1)
    return _Lexicon(lex, max(len(key) for key in lex), starts)


def _number(digits: str) -> int:
    """A run of digits as a count; a run longer than 9 digits counts as 10**9 (any count is
    capped far below; Python refuses to read runs of over 4300 digits)."""
    digits = digits.lstrip("0") or "0"
    return int(digits) if len(digits) <= 9 else 10**9


def _tokens(text: str) -> list[_Tok]:
    """Greedy longest-match tokens; a word nothing matches is UNK, digits are NUM."""
    lex = _lexicon()
    words = _words(text)
    toks: list[_Tok] = []
    i = 0
    while i < len(words):
        entry, n = None, 1
        for size in range(min(lex.longest, len(words) - i), 0, -1):
            found = lex.phrases.get(tuple(w for w, _, _ in words[i : i + size]))
            if found is None:
                continue
            ends_inside_noun = (
                found[0] != NOUN
                and size > 1
                and i + size < len(words)
                and (words[i + size - 1][0], words[i + size][0]) in lex.noun_starts
            )
            if not ends_inside_noun:
                entry, n = found, size
                break
        if entry is None:
            word = words[i][0]
            entry = (NUM, _number(word)) if word.isdigit() else (UNK, word)
        toks.append(_Tok(entry[0], entry[1], words[i][1], words[i + n - 1][2]))
        i += n
    return toks


# -- elements -------------------------------------------------------------------------------


@dataclass
class _NP:
    """A noun phrase: "the two large nightstands", "a bowl of fruit", "a spaceship"."""

    det: str | None
    count: int | None
    noun: _Noun | None
    """The head noun; None when the head is not understood (see ``unknown``)."""
    unknown: tuple[str, ...]
    """The not-understood words of a phrase without a known head."""
    trailing: tuple[str, ...]
    """Not-understood words after a known head ("lamp shade": ``shade``)."""
    phrase: str
    content: _NP | None = None
    """What an "of" phrase says it holds ("a bowl of fruit": fruit)."""
    mounted: bool = False
    """The phrase says its object hangs on a wall ("a wall-mounted TV", "a TV mounted ...",
    "a wall mirror")."""


@dataclass(frozen=True)
class _Pron:
    kind: str


@dataclass(frozen=True)
class _Seat:
    count: int
    phrase: str


@dataclass(frozen=True)
class _Mark:
    kind: str
    """COMMA, a conjunction, or SEP."""


@dataclass(frozen=True)
class _Mount:
    """A mount word without a noun phrase of its own ("the TV is wall mounted"): the latest
    object hangs on a wall."""


_Element = _NP | _Pron | _Cue | _Seat | _Mark | _Mount
_NP_START = frozenset({DET, NUM, MOD, UNK, NOUN, MOUNT})
_NP_BODY = frozenset({MOD, UNK, NOUN, MOUNT})
_DET_STRENGTH = (INDEF, DEF, BOTH, EACH, ANOTHER, NEG)


def _noun_phrase(text: str, toks: list[_Tok], i: int) -> tuple[_NP | _Pron | _Mount | None, int]:
    """The noun phrase starting at ``toks[i]`` (or the pronoun an elliptic "each" or "one"
    stands for, or a lone mount word) and the index after it."""
    start = toks[i].start
    det: str | None = None
    count: int | None = None
    while i < len(toks) and toks[i].kind in (DET, NUM):
        tok = toks[i]
        if tok.kind == DET:
            if det is None or _DET_STRENGTH.index(tok.value) > _DET_STRENGTH.index(det):
                det = tok.value
        elif count is None:
            count = tok.value
        i += 1
    body: list[_Tok] = []
    while i < len(toks) and toks[i].kind in _NP_BODY:
        body.append(toks[i])
        i += 1
    if count == 0:
        det = NEG
    heads = [k for k, tok in enumerate(body) if tok.kind == NOUN]
    unknown = [tok for tok in body if tok.kind == UNK]
    mount = any(tok.kind == MOUNT for tok in body)
    if heads:
        h = heads[-1]
        after = [tok for tok in body[h + 1 :] if tok.kind == UNK]
        end = after[-1].end if after else body[h].end
        trailing = tuple(tok.value for tok in after)
        # "a wall mirror", "a wall clock": the feature word before the head is where it hangs
        mount = mount or any(
            tok.kind == NOUN and tok.value == _Noun(FEATURE, WALL) for tok in body[:h]
        )
        return _NP(det, count, body[h].value, (), trailing, text[start:end], None, mount), i
    if unknown:
        words = tuple(tok.value for tok in unknown)
        return _NP(det, count, None, words, (), text[start : unknown[-1].end]), i
    if det in (EACH, BOTH):
        return _Pron(EACH), i
    if count is not None and det != NEG:
        return _Pron(ONE), i
    if mount and det is None and count is None:
        return _Mount(), i
    return None, i


def _elements(text: str, toks: list[_Tok]) -> list[_Element]:
    """Noun phrases, pronouns, cues, seating phrases and punctuation, in order."""
    out: list[_Element] = []
    i = 0
    while i < len(toks):
        tok = toks[i]
        if tok.kind in _NP_START:
            element, i = _noun_phrase(text, toks, i)
            if element is not None:
                out.append(element)
            continue
        i += 1
        if tok.kind == OF:
            prev = out[-1] if out else None
            if isinstance(prev, _NP) and prev.noun is not None and prev.content is None:
                if i < len(toks) and toks[i].kind in _NP_START:
                    content, i = _noun_phrase(text, toks, i)
                    if isinstance(content, _NP):
                        prev.content = content
        elif tok.kind == SEAT:
            seat, i = _seat_phrase(text, toks, i, tok.start)
            if seat is not None:
                out.append(seat)
        elif tok.kind == CUE:
            out.append(tok.value)
        elif tok.kind == PRON:
            out.append(_Pron(tok.value))
        elif tok.kind == CONJ:
            out.append(_Mark(tok.value))
        elif tok.kind == SEP:
            out.append(_Mark(SEP))
    return out


def _seat_phrase(text: str, toks: list[_Tok], i: int, start: int) -> tuple[_Seat | None, int]:
    """ "for eight (people)" / "seats 6": a number not followed by a noun; else nothing."""
    if i >= len(toks) or toks[i].kind != NUM or toks[i].value == 0:
        return None, i
    if i + 1 < len(toks) and toks[i + 1].kind in _NP_BODY:
        return None, i
    count = toks[i].value
    if i + 1 < len(toks) and toks[i + 1].kind == PEOPLE:
        i += 1
    return _Seat(count, text[start : toks[i].end]), i + 1


# -- the pass -------------------------------------------------------------------------------

_ROOM = "room"
"""The room itself, as a head or pronoun referent: relates nothing."""
_NOTHING = ""
"""A head that relates nothing: a room feature ("the floor") or words not understood."""
_FEATURES = {WALL: "@wall", WINDOW: "@window"}
"""Walls and windows as heads and anchors: they relate nothing, but what is put on them
hangs on a wall (:meth:`_Parser._hang_on`)."""


@dataclass
class _Object:
    category: str
    count: int
    phrase: str
    generic: str | None = None
    """The generic noun that named it ("lamp"), if one did."""
    counted: bool = False
    """The text gave its count ("two curtains"): the windows it hangs at do not change it."""
    wall: bool = False
    """It hangs on a wall."""
    per_feature: bool = False
    """Its count already follows the walls or windows it hangs on."""
    mid_room: bool = False
    """It stands clear of every wall (:attr:`TextSpec.mid_room`)."""
    facing: bool = False
    """It faces the object it is related to, or its instances face each other
    (:attr:`TextSpec.facing`)."""


@dataclass
class _Head:
    """An open "HEAD with ITEMS" list (the bottom one: the top level, ref None)."""

    ref: str | None
    each: bool = False
    cue: _Cue | None = None


@dataclass
class _Parser:
    """One left-to-right pass over the elements of a text."""

    room_type: str | None
    objects: dict[str, _Object] = field(default_factory=dict)
    recency: list[str] = field(default_factory=list)
    """Refs (and :data:`_ROOM`), least recently mentioned first."""
    relations: dict[tuple[str, str, str], tuple[bool, bool, bool, bool]] = field(
        default_factory=dict
    )
    """(kind, dependent, anchor) -> (each, explicit, over, across); implicit ones come from
    "with"."""
    unparsed: list[str] = field(default_factory=list)
    stack: list[_Head] = field(default_factory=lambda: [_Head(None)])
    group: list[str] = field(default_factory=list)
    """The current list's items, the candidates for the dependents of the next cue."""
    placed: set[str] = field(default_factory=set)
    """Objects already related by a cue: a later cue's list of dependents stops at them."""
    last: str | None = None
    last_each: bool = False
    negated: bool = False
    excluded: list[str] = field(default_factory=list)
    """Categories of negated phrases ("no desk", "0 beds"), in order."""
    pending: _Cue | None = None
    features: dict[str, _NP] = field(default_factory=dict)
    """The latest phrase naming each of :data:`_FEATURES` ("the windows")."""
    cued: tuple[str | None, list[str]] = (None, [])
    """The anchor and dependents of the latest cue that related objects."""

    def run(self, elements: list[_Element]) -> None:
        """Reads the elements in order; a dependent-first cue waits for its anchor."""
        for el in elements:
            if isinstance(el, _Cue) and not el.head_first:
                self._close_cue()
                self.pending = el
            elif self.pending is not None and isinstance(el, _NP | _Pron):
                cue, self.pending = self.pending, None
                self._apply_cue(cue, el)
            else:
                self._close_cue()
                self._dispatch(el)
        self._close_cue()
        self._imply_anchors()

    def _imply_anchors(self) -> None:
        """A mention whose name implies its anchor (:func:`implied_anchor`) and that the
        text relates to nothing takes the first mention of that anchor's category as its
        functional anchor: an implicit relation, which relates nothing already related and
        closes no cycle (:meth:`_relate`)."""
        for ref, obj in list(self.objects.items()):
            category = implied_anchor(obj.phrase)
            anchor = next((a for a, o in self.objects.items() if o.category == category), None)
            if anchor is not None:
                self._relate(FUNCTIONAL, ref, anchor, False, explicit=False)

    def spec(self, text: str) -> TextSpec:
        """The frozen result."""
        mentions = tuple(
            Mention(ref, o.category, o.count, o.phrase) for ref, o in self.objects.items()
        )
        relations = tuple(
            Relation(k, d, a, each, over, across)
            for (k, d, a), (each, _, over, across) in self.relations.items()
        )
        on_wall = tuple(ref for ref, o in self.objects.items() if o.wall)
        mid_room = tuple(ref for ref, o in self.objects.items()
                         if (o.mid_room or named_mid_room(o.phrase)) and not o.wall)  # fmt: skip
        unparsed = tuple(dict.fromkeys(self.unparsed))
        named = {m.category for m in mentions}
        excluded = tuple(c for c in dict.fromkeys(self.excluded) if c not in named)
        facing = tuple(ref for ref, o in self.objects.items() if o.facing and not o.wall)
        return TextSpec(text, self.room_type, mentions, relations, unparsed, on_wall,
                        mid_room, facing, excluded)  # fmt: skip

    # -- elements

    def _dispatch(self, el: _Element) -> None:
        """Any element but a dependent-first cue and its anchor."""
        if isinstance(el, _NP):
            self._item(el)
        elif isinstance(el, _Pron):
            self._item_pronoun(el)
        elif isinstance(el, _Cue):
            self._open(el)
        elif isinstance(el, _Seat):
            self._seat(el)
        elif isinstance(el, _Mount):
            if self.last in self.objects and not self.negated and not self._hang(self.last):
                if self.last == self.cued[0]:  # "a TV above the dresser, wall mounted"
                    for dep in self.cued[1]:
                        self._hang(dep)
        elif el.kind == COMMA:
            if len(self.stack) > 1 and self.stack[-2].ref is not None:
                self.stack.pop()
                self.group = []
            self.negated = False
        elif el.kind == SEP:
            self.stack, self.group, self.last, self.negated = [_Head(None)], [], None, False

    def _item(self, np: _NP) -> None:
        """A list item: a new or referred-to object, related to the open list's head."""
        if self.negated or np.det == NEG:
            self._exclude(np)
            return
        cue = self.stack[-1].cue
        ref, _ = self._refer(
            np, anchor=False, plural=FILL_COUNT if cue and cue.fill else PLURAL_COUNT
        )
        self.last, self.last_each = ref, np.det == EACH
        if ref in self.objects:
            self.group.append(ref)
            self._implicit(ref)

    def _exclude(self, np: _NP) -> None:
        """A negated phrase ("no desk", "0 beds", "without a TV"): none of its object."""
        if np.noun is None:
            return
        if np.noun.kind == OBJECT:
            self.excluded.append(np.noun.value)
        elif np.noun.kind == GENERIC:
            self.excluded.extend(GENERIC_NOUNS[np.noun.value])

    def _item_pronoun(self, pron: _Pron) -> None:
        """ "It has ...", "one on each side": a list item that refers back."""
        if self.negated:
            return
        ref = self._pronoun(pron.kind, anchor=False)
        if ref is None:
            return
        self._touch(ref)
        self.last, self.last_each = ref, pron.kind == EACH
        if ref in self.objects:
            self.group.append(ref)

    def _open(self, cue: _Cue) -> None:
        """A head-first cue: "with" opens a list of items relating to the last phrase."""
        if cue.kind == NEGATE:
            self.negated = True
            return
        self.stack.append(_Head(self.last, cue.each or self.last_each, cue))
        self.group, self.negated = [], False

    def _close_cue(self) -> None:
        """A cue followed by no phrase of its own relates to "it" ("pillows on top")."""
        if self.pending is not None:
            cue, self.pending = self.pending, None
            self._apply_cue(cue, None)

    def _apply_cue(self, cue: _Cue, target: _NP | _Pron | None) -> None:
        """A dependent-first cue: the trailing items of the list relate to the anchor."""
        head = self.stack[-1]
        created = False
        anchor: str | None
        if isinstance(target, _NP):
            anchor = None
            if not self.negated and target.det != NEG:
                anchor, created = self._refer(target, anchor=True)
            each = target.det in (EACH, BOTH)
        elif target is None and cue.middle:  # "in the middle of the room" ("room" is skipped)
            anchor, each = _ROOM, False
        elif isinstance(target, _Pron) and target.kind == RECIPROCAL:
            self._reciprocal(cue)
            return
        else:
            kind = target.kind if target is not None else IT
            anchor = self._pronoun(kind, anchor=True)
            each = kind == EACH or (anchor is not None and anchor == head.ref and head.each)
        run = self._run(anchor)
        self.placed.update(run)
        if anchor in self.features and isinstance(target, _NP):
            args = (cue.kind == SUPPORT, target.det in (EACH, BOTH))
            if not [dep for dep in run if self._hang_on(anchor, dep, *args)]:
                # "a lamp beside the bed on the wall": the bed does not hang, the lamp does
                if run == self.group == [self.cued[0]]:
                    for dep in self.cued[1]:
                        self._hang_on(anchor, dep, *args)
            return
        if anchor == _ROOM and cue.middle:  # "a table in the middle of the room"
            for dep in run:
                self.objects[dep].mid_room = True
        if anchor not in self.objects:
            return
        if created:
            self._implicit(anchor)
        if not cue.container or self.objects[anchor].category in CONTAINERS:
            for dep in run:
                related = self._relate(cue.kind, dep, anchor, each, explicit=True,
                                       over=cue.over, across=cue.across)  # fmt: skip
                if related and cue.pair:
                    self.objects[dep].count = max(self.objects[dep].count, 2)
        self.cued = (anchor, run)
        self.placed.add(anchor)
        self.group = [anchor]
        self.last, self.last_each = anchor, each

    def _reciprocal(self, cue: _Cue) -> None:
        """ "ITEMS <cue> each other": the later items relate to the first ("a sofa and an
        armchair facing each other": the armchair to the sofa); one item of two or more
        relates its instances ("two sofas facing each other", :attr:`TextSpec.facing`)."""
        run = self._run(None)
        self.placed.update(run)
        if cue.kind != FUNCTIONAL or not run:
            return
        first = run[0]
        for dep in run[1:]:
            self._relate(FUNCTIONAL, dep, first, False, explicit=True)
            self.objects[dep].facing |= cue.across
        if len(run) == 1 and self.objects[first].count > 1:
            self.objects[first].facing |= cue.across
        self.cued = (first, run)
        self.group = [first]
        self.last, self.last_each = first, False

    def _seat(self, seat: _Seat) -> None:
        """ "for eight": that many seats around the last table (a new dining table when the
        last phrase is a dining room); after seats ("chairs for six"), their count."""
        last = self.last
        if last in self.objects and self.objects[last].category in SEAT_TARGETS.values():
            self.objects[last].count = seat.count
            return
        if last in self.objects and self.objects[last].category in SEAT_TARGETS:
            target = last
        elif last in (None, _ROOM) and self.room_type in SEATING_ROOMS:
            found = self._recent(lambda o: o.category == "dining_table")
            target = found or self._new("dining_table", 1, seat.phrase)
        else:
            return
        seats = self._new(SEAT_TARGETS[self.objects[target].category], seat.count, seat.phrase)
        self._relate(FUNCTIONAL, seats, target, False, explicit=True)
        self.placed.update((seats, target))

    # -- references

    def _refer(self, np: _NP, anchor: bool, plural: int = PLURAL_COUNT) -> tuple[str, bool]:
        """The ref a noun phrase stands for (a reused or new mention, :data:`_ROOM` or
        :data:`_NOTHING`) and whether it is new. Anchors and definite phrases reuse the
        latest mention of their category; "another" never does."""
        if np.noun is None:
            self.unparsed.append(" ".join(np.unknown))
            return _NOTHING, False
        if np.trailing:
            self.unparsed.append(" ".join(np.trailing))
        if np.noun.kind == ROOM:
            self._touch(_ROOM)
            return _ROOM, False
        if np.noun.kind == FEATURE:
            feature = _FEATURES.get(np.noun.value)
            if feature is None:
                return _NOTHING, False
            self.features[feature] = np
            return feature, False
        reference = np.det != ANOTHER and (anchor or np.det in (DEF, EACH, BOTH))
        category = self._category(np.noun, reference)
        ref = self._recent(lambda o: o.category == category) if reference else None
        created = ref is None
        if ref is None:
            ref = self._new(category, self._count(np, plural), np.phrase)
            obj = self.objects[ref]
            obj.counted = np.count is not None
            obj.generic = np.noun.value if np.noun.kind == GENERIC else None
        else:
            self._touch(ref)
        if np.mounted:
            self._hang(ref)
        if np.content is not None:
            self._content(ref, np.content)
        return ref, created

    def _content(self, container: str, np: _NP) -> None:
        """ "a bowl of fruit": the content rests in the container (per instance)."""
        if np.det == NEG:
            return
        if np.noun is None:
            self.unparsed.append(" ".join(np.unknown))
            return
        if np.trailing:
            self.unparsed.append(" ".join(np.trailing))
        holder = self.objects[container]
        if np.noun.kind not in (OBJECT, GENERIC) or holder.category not in CONTAINERS:
            return
        ref = self._new(self._category(np.noun, False), self._count(np, CONTENT_COUNT), np.phrase)
        self._relate(SUPPORT, ref, container, holder.count > 1, explicit=True)
        self.placed.add(ref)

    def _category(self, noun: _Noun, reference: bool) -> str:
        """The category of a head noun; a generic one by reference or by default."""
        if noun.kind == OBJECT:
            return noun.value
        options = GENERIC_NOUNS[noun.value]
        if reference:
            ref = self._recent(lambda o: o.category in options)
            if ref is not None:
                return self.objects[ref].category
        return GENERIC_ROOM_DEFAULTS.get((noun.value, self.room_type or ""), options[0])

    @staticmethod
    def _count(np: _NP, plural: int) -> int:
        """The explicit count, else 2 for each/both, ``plural`` for a bare plural, else 1."""
        if np.count is not None:
            return np.count
        if np.det in (EACH, BOTH):
            return EACH_COUNT
        assert np.noun is not None
        return plural if np.noun.plural and np.det != INDEF else 1

    def _pronoun(self, kind: str, anchor: bool) -> str | None:
        """What "it"/"them"/"each" refers to. As an anchor: the open list's head, else the
        latest furniture or fixture other than the item just named (any object when there
        is none; "them": preferably one of several); as an item: the latest mention (or the
        room, for "it")."""
        if not anchor:
            for ref in reversed(self.recency):
                if ref in self.objects or kind == IT:
                    return ref
            return None
        head = self.stack[-1].ref
        item = self.group[-1] if self.group else None
        if head in self.objects and head != item:
            return head
        others = [ref for ref in reversed(self.recency) if ref in self.objects and ref != item]
        furniture = (SuperCategory.LARGE_FURNITURE, SuperCategory.FIXTURE)
        pool = [ref for ref in others if self._super(ref) in furniture] or others
        if kind in (THEM, EACH):
            pool = [ref for ref in pool if self.objects[ref].count > 1] or pool
        return pool[0] if pool else None

    def _run(self, anchor: str | None) -> list[str]:
        """The dependents of a cue: the list's last item and the items before it of the same
        super-category, back to the anchor or an item a cue already placed."""
        if not self.group or self.group[-1] == anchor:
            return []
        last = self.group[-1]
        run = [last]
        for ref in reversed(self.group[:-1]):
            if ref == anchor or ref in self.placed or self._super(ref) != self._super(last):
                break
            if ref not in run:
                run.insert(0, ref)
        return run

    # -- relations

    def _implicit(self, ref: str) -> None:
        """An item of an open "with" list relates to its head: small objects rest on it,
        anything else is placed relative to it (unless the cue says which). An item of the
        head's own category ("a desk with a lamp, a desk with a laptop") does not."""
        head = self.stack[-1]
        if head.ref in self.features and head.cue is not None:  # "a window with curtains"
            self._hang_on(head.ref, ref, head.cue.kind != FUNCTIONAL, head.each)
            return
        if head.ref not in self.objects or head.cue is None:
            return
        if self.objects[head.ref].category == self.objects[ref].category:
            return
        kind = head.cue.kind
        if kind == WITH:
            small = self._super(ref) is SuperCategory.SMALL_OBJECT
            kind = SUPPORT if small else FUNCTIONAL
        assert head.ref is not None
        self._relate(kind, ref, head.ref, head.each, explicit=False)

    def _relate(
        self, kind: str, dep: str, anchor: str, each: bool, explicit: bool,
        over: bool = False, across: bool = False,
    ) -> bool:  # fmt: skip
        """Adds a relation unless it would close a cycle. An explicit relation replaces the
        dependent's implicit ones and its earlier relation of the same kind; an implicit one
        never replaces anything."""
        if dep == anchor or dep in self._anchors_of(anchor):
            return False
        if kind == SUPPORT and self.objects[dep].wall:
            if not explicit:  # "a bed with a wall-mounted TV": by the bed, on a wall
                kind = FUNCTIONAL
            else:  # the text puts it on something after all: the latest word wins
                self.objects[dep].wall = False
        mine = {key: value for key, value in self.relations.items() if key[1] == dep}
        if explicit:
            for key, (_, was_explicit, _, _) in mine.items():
                if not was_explicit or key[0] == kind:
                    del self.relations[key]
        elif mine:
            return False
        self.relations[(kind, dep, anchor)] = (each, explicit, over, across)
        return True

    def _hang(self, ref: str) -> bool:
        """Hangs a mention on a wall (a generic lamp becomes a wall lamp); False when its
        category does not hang (:data:`MOUNTABLE`). Its support relation becomes a
        functional one unless it has one ("a desk with a lamp on the wall": by the desk)."""
        obj = self.objects[ref]
        if obj.category not in MOUNTABLE:
            if obj.generic != "lamp":
                return False
            obj.category = WALL_LAMP
        obj.wall = True
        for key in [key for key in self.relations if key[0] == SUPPORT and key[1] == ref]:
            value = self.relations.pop(key)
            if not any(k[0] == FUNCTIONAL and k[1] == ref for k in self.relations):
                self.relations[(FUNCTIONAL, ref, key[2])] = value
        return True

    def _hang_on(self, feature: str, ref: str, support: bool, each: bool) -> bool:
        """A mention put on a wall ("on the wall": ``support``) or related to windows (any
        cue, curtains and blinds only) hangs on a wall; its count follows the walls or
        windows: per wall or window for each/both ("a painting on every wall", "curtains
        on both windows"), and one per window named when the text gave no count of its own
        ("curtains on the windows": two). Whether it hangs."""
        obj = self.objects[ref]
        if feature == _FEATURES[WINDOW]:
            if obj.category not in WINDOW_DRESSINGS:
                return False  # "a desk by the window": where it stands, as before
        elif not support:
            return False  # "a bed against the wall"
        if not self._hang(ref):
            return False
        if obj.per_feature:
            return True
        np = self.features[feature]
        each = each or np.det in (EACH, BOTH)
        if np.count is not None:
            n = np.count
        elif np.det == EACH:
            n = WALLS_PER_ROOM if feature == _FEATURES[WALL] else EACH_COUNT
        elif np.det == BOTH or (np.noun is not None and np.noun.plural):
            n = PLURAL_COUNT
        else:
            n = 1
        if each:
            obj.count *= max(n, 1)
            obj.per_feature = True
        elif feature == _FEATURES[WINDOW] and not obj.counted:
            obj.count = max(obj.count, n)
            obj.per_feature = True
        return True

    def _anchors_of(self, ref: str) -> set[str]:
        """Every mention ``ref`` depends on, directly or not."""
        seen: set[str] = set()
        todo = [ref]
        while todo:
            cur = todo.pop()
            for _, dep, anchor in self.relations:
                if dep == cur and anchor not in seen:
                    seen.add(anchor)
                    todo.append(anchor)
        return seen

    # -- mentions

    def _new(self, category: str, count: int, phrase: str) -> str:
        """A new mention, the most recent one."""
        ref = f"m{len(self.objects)}"
        self.objects[ref] = _Object(category, count, phrase)
        self._touch(ref)
        return ref

    def _touch(self, ref: str) -> None:
        """Marks ``ref`` as the most recently mentioned."""
        if ref in self.recency:
            self.recency.remove(ref)
        self.recency.append(ref)

    def _recent(self, accept: Callable[[_Object], bool]) -> str | None:
        """The most recently mentioned object ``accept`` takes, if any."""
        for ref in reversed(self.recency):
            if ref in self.objects and accept(self.objects[ref]):
                return ref
        return None

    def _super(self, ref: str) -> SuperCategory:
        """The super-category of a mention."""
        return BY_NAME[self.objects[ref].category].super


def _named_room(elements: list[_Element]) -> str | None:
    """The first room the text names (not as a modifier, not negated)."""
    for el in elements:
        if isinstance(el, _NP) and el.noun is not None and el.noun.kind == ROOM and el.det != NEG:
            return el.noun.value
    return None


def _check_tables() -> None:
    """Every category the tables name exists and is an object category."""
    bad = sorted(
        name
        for name in (*EXTRA_SYNONYMS.values(), *GENERIC_ROOM_DEFAULTS.values(), *CONTAINERS,
                     *SEAT_TARGETS, *SEAT_TARGETS.values(), *MOUNTABLE, *WINDOW_DRESSINGS,
                     WALL_LAMP, *(c for options in GENERIC_NOUNS.values() for c in options))
        if name not in BY_NAME
        or BY_NAME[name].super in (SuperCategory.STRUCTURE, SuperCategory.PART)
    )  # fmt: skip
    features = [f for f in _FEATURES if BY_NAME.get(f) is None or BY_NAME[f].super
                is not SuperCategory.STRUCTURE]  # fmt: skip
    if bad or features or not WINDOW_DRESSINGS <= MOUNTABLE:  # a programming error here
        raise AssertionError(f"text tables name unknown or non-object categories: {bad}")


_check_tables()


# -- public ---------------------------------------------------------------------------------


MAX_TEXT_CHARS = 2000
"""A description longer than this is cut here (with a note): a room's description is a
few sentences, and the parser's work and the objects it names grow with the text."""

_NEGATIVE_COUNT = re.compile(r"(?<![\w\-−])[-−]\d+(?:[.,]\d+)?(?:\s+[^\W\d_]+)?")
"""A minus sign right before a number ("-5 beds"), not a range ("3-4 chairs") or a
list's dash ("- 2 chairs"), with the word after it."""


def limit_text(text: str) -> tuple[str, list[str]]:
    """A room description as it is read, and notes on what was done to it: cut at
    :data:`MAX_TEXT_CHARS` characters (at the last word break before, leading white space
    first dropped). A UserError for an empty text and for a negative count ("-5 beds":
    a count must be a positive number). The one gate of every text, the offline
    parser's (:func:`parse_text`) and the LLM's."""
    if not isinstance(text, str) or not text.strip():
        raise UserError("the room description is empty")
    notes = []
    body = text.lstrip()
    if len(body) > MAX_TEXT_CHARS:
        cut = body[:MAX_TEXT_CHARS]
        space = max(cut.rfind(" "), cut.rfind("\n"), cut.rfind("\t"))
        cut = cut[:space] if space > MAX_TEXT_CHARS // 2 else cut
        notes.append(
            f"the description was cut at {len(cut)} of its {len(body)} characters "
            f"(MAX_TEXT_CHARS {MAX_TEXT_CHARS}): the rest was not read"
        )
        text = cut
    negative = _NEGATIVE_COUNT.search(text)
    if negative is not None:
        raise UserError(
            f"{negative.group()!r} in the description: a count must be a positive number "
            "(write '0 ...' or 'no ...' for none)"
        )
    return text, notes


def parse_text(text: str) -> TextSpec:
    """The room type, requested objects and their relations in a room description.

    Raises :class:`~pair2scene.errors.UserError` when the text is empty, has a negative
    count or names neither a room type nor any known object; words it does not understand
    otherwise only end up in :attr:`TextSpec.unparsed`. A text longer than
    :data:`MAX_TEXT_CHARS` is read up to there (:func:`limit_text`, a note in
    :attr:`TextSpec.notes`).
    """
    text, notes = limit_text(text)
    elements = _elements(text, _tokens(text))
    parser = _Parser(_named_room(elements))
    parser.run(elements)
    spec = replace(parser.spec(text), notes=tuple(notes))
    if spec.room_type is None and not spec.mentions:
        shown = " ".join(text.split())
        shown = shown if len(shown) <= 60 else shown[:57] + "..."
        raise UserError(f"no room type and no known object in the description {shown!r}")
    return spec


def named_mid_room(phrase: str) -> bool:
    """Whether a mention's name is one of :data:`MID_ROOM_NAMES` ("two kitchen islands")."""
    return _names(phrase, MID_ROOM_NAMES) is not None


def _names(phrase: str, names) -> str | None:
    """The first of ``names`` that ``phrase`` holds as whole words, singular or plural."""
    words = " ".join(re.findall(r"[a-z]+", phrase.lower()))
    for name in names:
        forms = "|".join(re.escape(" ".join(k)) for k in {_key(name), *_plural_keys(_key(name))})
        if re.search(rf"\b(?:{forms})\b", words):
            return name
    return None


def implied_anchor(phrase: str) -> str | None:
    """The category a mention's name says it stands at (:data:`IMPLIED_ANCHORS`:
    "two nightstands" -> ``bed``), or None."""
    name = _names(phrase, IMPLIED_ANCHORS)
    return None if name is None else IMPLIED_ANCHORS[name]


def category_of(phrase: str) -> str | None:
    """The canonical category a noun phrase names, as :func:`parse_text` reads it
    ("nightstands" -> ``side_table``, "couch" -> ``sofa``, "coffee mugs" -> ``mug``);
    None for a room, a room feature, or words it does not know."""
    for el in _elements(phrase, _tokens(phrase)):
        if isinstance(el, _NP):
            if el.noun is None or el.noun.kind not in (OBJECT, GENERIC):
                return None
            if el.noun.kind == OBJECT:
                return el.noun.value
            return GENERIC_NOUNS[el.noun.value][0]
    return None
