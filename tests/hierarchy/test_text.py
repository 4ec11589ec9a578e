from __future__ import annotations

import pytest

from pair2scene.categories import BY_NAME, SuperCategory
from pair2scene.errors import UserError
from pair2scene.hierarchy.text import Mention, Relation, TextSpec, category_of, parse_text


def counts(spec: TextSpec) -> list[tuple[str, int]]:
    """(category, count) of every mention, in order."""
    return [(m.category, m.count) for m in spec.mentions]


def links(spec: TextSpec) -> set[tuple[str, str, str, bool]]:
    """Relations as (kind, dependent category, anchor category, each)."""
    cat = {m.ref: m.category for m in spec.mentions}
    return {(r.kind, cat[r.dependent], cat[r.anchor], r.each) for r in spec.relations}


def ref(spec: TextSpec, category: str) -> str:
    (found,) = [m.ref for m in spec.mentions if m.category == category]
    return found


def test_headline_lamp_on_each_nightstand():
    spec = parse_text("a bedroom with two nightstands and a lamp on each nightstand")
    assert spec.room_type == "bedroom"
    assert counts(spec) == [("side_table", 2), ("table_lamp", 1)]
    lamp, nightstand = ref(spec, "table_lamp"), ref(spec, "side_table")
    assert spec.relations == (Relation("support", lamp, nightstand, each=True),)
    assert [m.phrase for m in spec.mentions] == ["two nightstands", "a lamp"]
    assert [m.ref for m in spec.mentions] == ["m0", "m1"]
    assert spec.unparsed == ()


def test_list_with_each_reuses_the_mentioned_nightstands():
    spec = parse_text("a bedroom with a bed, two nightstands and a lamp on each nightstand")
    assert counts(spec) == [("bed", 1), ("side_table", 2), ("table_lamp", 1)]
    assert links(spec) == {
        ("support", "table_lamp", "side_table", True),
        ("functional", "side_table", "bed", False),  # a nightstand stands at the bed
    }


@pytest.mark.parametrize(
    "text, expected",
    [
        ("a bedroom with a double bed, two nightstands and a wardrobe",
         {("functional", "side_table", "bed", False)}),
        ("a kitchen with an island and four bar stools",
         {("functional", "stool", "counter_top", False)}),
        ("a dining room with a dining table and six dining chairs",
         {("functional", "chair", "dining_table", False)}),
        ("an office with a desk and an office chair", {("functional", "chair", "desk", False)}),
        # the text's own relation stands; a name implies nothing against it
        ("a bedroom with a bed and a nightstand beside the desk",
         {("functional", "bed", "desk", False), ("functional", "side_table", "desk", False)}),
        # the anchor placed relative to the nightstand: no cycle
        ("a bedroom with a nightstand and a bed beside the nightstand",
         {("functional", "bed", "side_table", False)}),
        # plain stools and chairs say nothing of where they stand; no bed, no anchor
        ("a kitchen with an island and four stools", set()),
        ("a bedroom with a desk and a chair", set()),
        ("a room with two nightstands", set()),
    ],
)  # fmt: skip
def test_a_name_that_says_what_its_object_stands_at_relates_it(text, expected):
    assert links(parse_text(text)) == expected


def test_implied_anchor_reads_singular_and_plural_names():
    from pair2scene.hierarchy.text import implied_anchor

    assert implied_anchor("two nightstands") == "bed"
    assert implied_anchor("the Night Stands") == "bed"
    assert implied_anchor("a bedside table") == "bed"
    assert implied_anchor("4 barstools") == "counter_top"
    assert implied_anchor("some stools") is None
    assert implied_anchor("a standing lamp") is None
    assert category_of("a reading chair") == "armchair"


def test_with_list_and_on_it():
    spec = parse_text("a desk with a monitor and a keyboard on it and a chair")
    assert spec.room_type is None
    assert counts(spec) == [("desk", 1), ("monitor", 1), ("keyboard", 1), ("chair", 1)]
    assert links(spec) == {
        ("support", "monitor", "desk", False),
        ("support", "keyboard", "desk", False),
        ("functional", "chair", "desk", False),
    }


def test_kitchen_table_chairs_around_it_and_a_bowl_of_fruit():
    text = "a kitchen with a dining table, four chairs around it, and a bowl of fruit on the table"
    spec = parse_text(text)
    assert spec.room_type == "kitchen"
    assert counts(spec) == [("dining_table", 1), ("chair", 4), ("bowl", 1), ("apple", 3)]
    assert links(spec) == {
        ("functional", "chair", "dining_table", False),
        ("support", "bowl", "dining_table", False),
        ("support", "apple", "bowl", False),
    }


def test_each_with_relates_per_desk():
    spec = parse_text("an office with two desks, each with a chair and a laptop")
    assert spec.room_type == "office"
    assert counts(spec) == [("desk", 2), ("chair", 1), ("laptop", 1)]
    assert links(spec) == {
        ("functional", "chair", "desk", True),
        ("support", "laptop", "desk", True),
    }


def test_comma_closes_a_nested_with_list():
    text = "a living room with a sofa, a coffee table with a remote on it, and a tv on a tv stand"
    spec = parse_text(text)
    assert spec.room_type == "living_room"
    assert counts(spec) == [
        ("sofa", 1),
        ("coffee_table", 1),
        ("remote_control", 1),
        ("television", 1),
        ("tv_stand", 1),
    ]
    assert links(spec) == {
        ("support", "remote_control", "coffee_table", False),
        ("support", "television", "tv_stand", False),
    }


@pytest.mark.parametrize(
    "text, dependent, anchor",
    [
        ("a sofa facing the tv", "sofa", "television"),
        ("a nightstand next to the bed", "side_table", "bed"),
        ("a nightstand beside the bed", "side_table", "bed"),
        ("a chair at the desk", "chair", "desk"),
        ("chairs around the table", "chair", "dining_table"),
        ("a painting above the sofa", "painting", "sofa"),
        ("an armchair in front of the fireplace and a lamp behind the armchair", "table_lamp",
         "armchair"),
    ],
)  # fmt: skip
def test_functional_cues(text, dependent, anchor):
    spec = parse_text(text)
    assert ("functional", dependent, anchor, False) in links(spec)


def test_chairs_at_the_table_bare_plural_counts_two():
    spec = parse_text("chairs at the table")
    assert counts(spec) == [("chair", 2), ("dining_table", 1)]


@pytest.mark.parametrize(
    "text, expected",
    [
        ("a desk with a laptop", ("support", "laptop", "desk", False)),
        ("a desk with a chair", ("functional", "chair", "desk", False)),
        ("a bed with two pillows", ("support", "pillow", "bed", False)),
        ("a dresser with a mirror", ("functional", "mirror", "dresser", False)),
        ("a table surrounded by chairs", ("functional", "chair", "dining_table", False)),
        ("a tray holding cups", None),
    ],
)
def test_with_depends_on_the_item(text, expected):
    spec = parse_text(text)
    assert links(spec) == ({expected} if expected else set())


@pytest.mark.parametrize(
    "text, seat, count",
    [
        ("a dining table for eight", "chair", 8),
        ("a dining table for 8 people", "chair", 8),
        ("a table that seats six", "chair", 6),
        ("a kitchen island that seats four", "stool", 4),
    ],
)
def test_seating_adds_seats_around_the_table(text, seat, count):
    spec = parse_text(text)
    table = spec.mentions[0]
    assert table.count == 1
    seats = [m for m in spec.mentions if m.category == seat]
    assert [m.count for m in seats] == [count]
    assert spec.relations == (Relation("functional", seats[0].ref, table.ref, each=False),)


def test_a_dining_room_for_eight_gets_a_table_and_chairs():
    spec = parse_text("a dining room for eight")
    assert spec.room_type == "dining_room"
    assert counts(spec) == [("dining_table", 1), ("chair", 8)]
    assert links(spec) == {("functional", "chair", "dining_table", False)}


def test_chairs_for_six_sets_their_count():
    spec = parse_text("a dining table with chairs for six")
    assert counts(spec) == [("dining_table", 1), ("chair", 6)]


@pytest.mark.parametrize(
    "text, holder",
    [("a shelf full of books", "shelving_unit"), ("a bookcase filled with books", "shelving_unit")],
)
def test_full_of_counts_five(text, holder):
    spec = parse_text(text)
    assert counts(spec) == [(holder, 1), ("book", 5)]
    assert links(spec) == {("support", "book", holder, False)}


def test_books_on_the_shelf():
    spec = parse_text("books on the shelf")
    assert counts(spec) == [("book", 2), ("shelving_unit", 1)]
    assert links(spec) == {("support", "book", "shelving_unit", False)}


def test_in_relates_only_to_containers():
    spec = parse_text("plates in the cabinet")
    assert links(spec) == {("support", "plate", "cabinet", False)}
    spec = parse_text("a chair in the dining room")
    assert spec.room_type == "dining_room"
    assert counts(spec) == [("chair", 1)]
    assert spec.relations == ()
    assert parse_text("a lamp in the corner").relations == ()


def test_two_pillows_on_each_bed():
    spec = parse_text("two pillows on each bed")
    assert counts(spec) == [("pillow", 2), ("bed", 2)]
    assert links(spec) == {("support", "pillow", "bed", True)}


@pytest.mark.parametrize(
    "text, count",
    [
        ("a chair", 1),
        ("one chair", 1),
        ("an armchair", 1),
        ("two chairs", 2),
        ("3 chairs", 3),
        ("twelve chairs", 12),
        ("a pair of chairs", 2),
        ("a couple of chairs", 2),
        ("several chairs", 3),
        ("a few chairs", 2),
        ("some chairs", 2),
        ("lots of chairs", 5),
        ("many chairs", 5),
        ("a dozen chairs", 12),
        ("chairs", 2),
        ("chair", 1),
    ],
)
def test_counts(text, count):
    spec = parse_text(text)
    assert [m.count for m in spec.mentions] == [count]
    assert spec.mentions[0].phrase == text


@pytest.mark.parametrize(
    "phrase, category",
    [
        ("nightstands", "side_table"),
        ("bedside table", "side_table"),
        ("Side_Table", "side_table"),
        ("couch", "sofa"),
        ("couches", "sofa"),
        ("sofas", "sofa"),
        ("coffee mugs", "mug"),
        ("bookshelf", "shelving_unit"),
        ("bookshelves", "shelving_unit"),
        ("bookcases", "shelving_unit"),
        ("shelves", "shelving_unit"),
        ("tv", "television"),
        ("telly", "television"),
        ("fridge", "fridge"),
        ("refrigerator", "fridge"),
        ("knives", "knife"),
        ("glasses", "cup"),
        ("dishes", "plate"),
        ("boxes", "box"),
        ("benches", "ottoman"),
        ("potatoes", "potato"),
        ("chests of drawers", "dresser"),
        ("desk lamp", "table_lamp"),
        ("lamps", "table_lamp"),
        ("floor lamp", "floor_lamp"),
        ("coffee table", "coffee_table"),
        ("table", "dining_table"),
        ("a bowl of fruit", "bowl"),
        ("curtains", "curtains"),
    ],
)
def test_category_of(phrase, category):
    assert category_of(phrase) == category


@pytest.mark.parametrize("phrase", ["floor", "wall", "drawer", "bedroom", "spaceship", ""])
def test_category_of_unknown_rooms_and_features_is_none(phrase):
    assert category_of(phrase) is None


@pytest.mark.parametrize(
    "text, category",
    [
        ("a floor lamp", "floor_lamp"),
        ("a desk lamp", "table_lamp"),
        ("a coffee table", "coffee_table"),
        ("a chest of drawers", "dresser"),
        ("a tv stand", "tv_stand"),
        ("toilet paper", "toilet_paper"),
    ],
)
def test_longest_match_wins(text, category):
    assert counts(parse_text(text)) == [(category, 1)]


@pytest.mark.parametrize(
    "text, room",
    [
        ("a bedroom", "bedroom"),
        ("a master bedroom", "bedroom"),
        ("a kid's room", "kids_room"),  # composed types (resources/room_types.json)
        ("a children's room", "kids_room"),
        ("a nursery", "bedroom"),
        ("a living room", "living_room"),
        ("a lounge", "living_room"),
        ("a family room", "living_room"),
        ("a kitchen", "kitchen"),
        ("a bathroom", "bathroom"),
        ("a restroom", "bathroom"),
        ("a washroom", "bathroom"),
        ("a dining room", "dining_room"),
        ("an office", "office"),
        ("a study", "study"),
        ("a library", "study"),
        ("a home office", "office"),
        ("a workspace", "office"),
        ("a studio apartment", "apartment"),
        ("a studio", "apartment"),
        ("an apartment", "apartment"),
        ("a flat", "apartment"),
    ],
)
def test_room_types_are_not_objects(text, room):
    spec = parse_text(text)
    assert spec.room_type == room
    assert spec.mentions == spec.relations == spec.unparsed == ()


def test_room_word_as_modifier_names_no_room():
    spec = parse_text("a kitchen table and an office chair")
    assert spec.room_type is None
    assert counts(spec) == [("dining_table", 1), ("chair", 1)]


def test_definite_phrases_refer_back():
    spec = parse_text("a bed and a nightstand next to the bed")
    assert counts(spec) == [("bed", 1), ("side_table", 1)]
    spec = parse_text("a desk and a chair. The chair is at the desk.")
    assert counts(spec) == [("desk", 1), ("chair", 1)]
    assert links(spec) == {("functional", "chair", "desk", False)}


def test_generic_table_refers_to_the_latest_table():
    spec = parse_text("a sofa, a coffee table and a remote on the table")
    assert counts(spec) == [("sofa", 1), ("coffee_table", 1), ("remote_control", 1)]
    assert links(spec) == {("support", "remote_control", "coffee_table", False)}
    assert counts(parse_text("a bedroom with a table")) == [("side_table", 1)]


def test_another_and_indefinite_items_make_new_mentions():
    spec = parse_text("a lamp on the desk and another lamp on the nightstand")
    assert counts(spec) == [("table_lamp", 1), ("desk", 1), ("table_lamp", 1), ("side_table", 1)]
    assert links(spec) == {
        ("support", "table_lamp", "desk", False),
        ("support", "table_lamp", "side_table", False),
    }


@pytest.mark.parametrize(
    "text, each",
    [
        ("two nightstands with lamps on them", False),
        ("two nightstands with a lamp on each", True),
        ("two nightstands, each with a lamp", True),
        ("a lamp on both nightstands", True),
    ],
)
def test_pronouns_and_elliptic_each(text, each):
    spec = parse_text(text)
    assert links(spec) == {("support", "table_lamp", "side_table", each)}
    assert ("side_table", 2) in counts(spec)


def test_it_prefers_furniture_then_any_object():
    spec = parse_text("a bedroom with a bed and two nightstands next to it")
    assert links(spec) == {("functional", "side_table", "bed", False)}
    spec = parse_text("a living room with a tv on the wall and a sofa facing it")
    assert links(spec) == {("functional", "sofa", "television", False)}


def test_a_new_sentence_starts_a_new_list():
    spec = parse_text("A bedroom. Put a lamp on each nightstand.")
    assert spec.room_type == "bedroom"
    assert counts(spec) == [("table_lamp", 1), ("side_table", 2)]
    assert links(spec) == {("support", "table_lamp", "side_table", True)}


def test_pair_cue_means_one_per_side():
    spec = parse_text("a bed with a nightstand on either side")
    assert counts(spec) == [("bed", 1), ("side_table", 2)]
    assert links(spec) == {("functional", "side_table", "bed", False)}
    spec = parse_text("the bedroom has a queen size bed flanked by two nightstands")
    assert counts(spec) == [("bed", 1), ("side_table", 2)]
    assert links(spec) == {("functional", "side_table", "bed", False)}


def test_room_features_are_understood_but_not_objects():
    spec = parse_text("a painting on the wall and a tv on the wall facing the sofa")
    assert counts(spec) == [("painting", 1), ("television", 1), ("sofa", 1)]
    assert links(spec) == {("functional", "television", "sofa", False)}
    assert spec.unparsed == ()


def test_negation_drops_objects():
    spec = parse_text("a bedroom without a tv, with a bed and no desk")
    assert spec.room_type == "bedroom"
    assert counts(spec) == [("bed", 1)]


def test_unknown_words_are_reported_not_raised():
    spec = parse_text("a bedroom with a spaceship")
    assert spec.room_type == "bedroom"
    assert spec.mentions == ()
    assert spec.unparsed == ("spaceship",)
    spec = parse_text("a bed, a rug on the floor and a vase of flowers")
    assert counts(spec) == [("bed", 1), ("vase", 1)]
    assert spec.unparsed == ("rug", "flowers")


def test_modifiers_and_filler_words_are_silent():
    spec = parse_text("I want a cozy little bedroom with a large wooden double bed, please")
    assert spec.room_type == "bedroom"
    assert counts(spec) == [("bed", 1)]
    assert spec.mentions[0].phrase == "a large wooden double bed"
    assert spec.unparsed == ()


def test_case_and_punctuation_do_not_matter():
    a = parse_text("A BEDROOM WITH TWO NIGHTSTANDS AND A LAMP ON EACH NIGHTSTAND!")
    b = parse_text("a bedroom with two nightstands and a lamp on each nightstand")
    assert (a.room_type, a.mentions[0].category, a.relations) == (
        b.room_type,
        b.mentions[0].category,
        b.relations,
    )


@pytest.mark.parametrize("text", ["", "   \n", "xyzzy blorp", "the of and", "a window and a door"])
def test_nothing_understood_is_a_user_error(text):
    with pytest.raises(UserError) as err:
        parse_text(text)
    assert "\n" not in str(err.value)


ALL_TEXTS = [
    "a bedroom with a bed, two nightstands and a lamp on each nightstand",
    "a desk with a monitor and a keyboard on it and a chair",
    "a kitchen with a dining table, four chairs around it, and a bowl of fruit on the table",
    "an office with two desks, each with a chair and a laptop",
    "a living room with a sofa, a coffee table with a remote on it, and a tv on a tv stand",
    "a couch with a coffee table in front of it and a tv on the wall across from the couch",
    "a lamp on a desk, the desk on the lamp",
    "a lamp on the desk. The lamp on the nightstand.",
    "a bathroom with a bathtub, a towel on the towel rack, and a toilet with toilet paper",
    "two bowls of fruit on the counter and a kettle next to the stove",
]


@pytest.mark.parametrize("text", ALL_TEXTS)
def test_specs_are_consistent_and_deterministic(text):
    spec = parse_text(text)
    assert spec == parse_text(text)
    refs = [m.ref for m in spec.mentions]
    assert refs == [f"m{i}" for i in range(len(refs))]
    for m in spec.mentions:
        assert m.count >= 1
        assert BY_NAME[m.category].super not in (SuperCategory.STRUCTURE, SuperCategory.PART)
    kinds = [(r.dependent, r.kind) for r in spec.relations]
    assert len(kinds) == len(set(kinds))
    anchors = {r.dependent: set() for r in spec.relations}
    for r in spec.relations:
        assert {r.dependent, r.anchor} <= set(refs) and r.dependent != r.anchor
        anchors[r.dependent].add(r.anchor)

    def reaches(start: str, goal: str, seen: frozenset = frozenset()) -> bool:
        return any(
            a == goal or (a not in seen and reaches(a, goal, seen | {a}))
            for a in anchors.get(start, ())
        )

    assert not any(reaches(r, r) for r in refs)


def test_cycles_are_never_created():
    spec = parse_text("a lamp on a desk, the desk on the lamp")
    assert links(spec) == {("support", "table_lamp", "desk", False)}


def test_dataclasses_validate():
    with pytest.raises(ValueError):
        Mention("m0", "chair", 0, "no chairs")
    with pytest.raises(ValueError):
        Relation("beside", "m0", "m1", each=False)
