"""The canonical category vocabulary and the label tables of every source.

Categories, super-categories and room types are defined here once; every
stage imports them from this module. A source label that no table maps is
counted by :class:`LabelMapper` and becomes ``unknown`` — never dropped.
"""

from __future__ import annotations

import re
from collections import Counter
from dataclasses import dataclass, field
from enum import Enum


class SuperCategory(str, Enum):
    LARGE_FURNITURE = "large_furniture"
    """Stands on the floor and is placed relative to the room: beds, tables, sofas."""
    SMALL_OBJECT = "small_object"
    """Rests on furniture (sometimes the floor): books, mugs, lamps, pillows."""
    WALL_OBJECT = "wall_object"
    """Hangs on a wall: paintings, mirrors, curtains."""
    FIXTURE = "fixture"
    """Built into the room: counters, sinks, toilets, bathtubs, showers."""
    PART = "part"
    """A movable part of another object: drawers, cabinet doors, shelves of a unit."""
    STRUCTURE = "structure"
    """The room itself: floor, walls, windows, doors. Room features, not objects."""
    UNKNOWN = "unknown"


LF, SO, WO, FX, PT, ST = (
    SuperCategory.LARGE_FURNITURE,
    SuperCategory.SMALL_OBJECT,
    SuperCategory.WALL_OBJECT,
    SuperCategory.FIXTURE,
    SuperCategory.PART,
    SuperCategory.STRUCTURE,
)


@dataclass(frozen=True)
class Category:
    name: str
    """Canonical snake_case name."""
    super: SuperCategory
    synonyms: tuple[str, ...] = field(default=())
    """Other English names (used by text parsing later)."""


UNKNOWN = "unknown"

# fmt: off
CATEGORIES: tuple[Category, ...] = (
    # large furniture
    Category("bed", LF, ("double bed", "king-size bed", "single bed", "bunk bed", "kids bed")),
    Category("sofa", LF, ("couch", "loveseat", "settee")),
    Category("armchair", LF, ("arm chair", "lounge chair", "easy chair")),
    Category("chair", LF, ("dining chair", "office chair", "desk chair")),
    Category("stool", LF, ("bar stool", "barstool")),
    Category("ottoman", LF, ("footstool", "pouf", "foot stool")),
    Category("dining_table", LF, ("dining table", "kitchen table")),
    Category("coffee_table", LF, ("coffee table", "cocktail table")),
    Category("side_table", LF, ("side table", "nightstand", "night stand", "bedside table",
                                "end table")),
    Category("desk", LF, ("writing desk", "computer desk")),
    Category("dressing_table", LF, ("dressing table", "vanity")),
    Category("dresser", LF, ("chest of drawers", "drawer chest")),
    Category("wardrobe", LF, ("closet", "armoire")),
    Category("cabinet", LF, ("sideboard", "console table", "side cabinet", "wine cabinet",
                             "cupboard")),
    Category("tv_stand", LF, ("tv stand", "tv unit", "media console")),
    Category("shelving_unit", LF, ("shelving unit", "bookcase", "bookshelf", "shelf unit")),
    Category("floor_lamp", LF, ("floor lamp", "standing lamp")),
    Category("garbage_can", LF, ("garbage can", "trash can", "bin", "wastebasket")),
    Category("fridge", LF, ("refrigerator",)),
    Category("laundry_hamper", LF, ("laundry hamper", "hamper", "laundry basket")),
    Category("safe", LF, ()),
    Category("dog_bed", LF, ("dog bed", "pet bed")),
    Category("house_plant", LF, ("house plant", "plant", "potted plant")),
    Category("vacuum_cleaner", LF, ("vacuum cleaner", "vacuum")),
    Category("cart", LF, ("kitchen cart", "trolley", "serving cart")),
    # fixtures
    Category("counter_top", FX, ("counter", "countertop", "kitchen counter")),
    Category("sink", FX, ("basin", "washbasin")),
    Category("toilet", FX, ("wc",)),
    Category("bathtub", FX, ("bath", "tub")),
    Category("shower", FX, ("shower door", "shower glass", "shower curtain", "shower head")),
    Category("towel_holder", FX, ("towel holder", "towel rail", "hand towel holder")),
    Category("toilet_paper_hanger", FX,
             ("toilet paper hanger", "toilet roll holder", "toilet paper holder")),
    Category("faucet", FX, ("tap",)),
    Category("stove", FX, ("cooktop", "hob", "stove burner")),
    Category("ceiling_lamp", FX, ("ceiling lamp", "pendant lamp", "chandelier")),
    # parts
    Category("drawer", PT, ()),
    Category("cabinet_door", PT, ("cabinet door",)),
    Category("shelf", PT, ("wall shelf",)),
    Category("stove_knob", PT, ("stove knob",)),
    Category("sink_basin", PT, ("sink basin",)),
    Category("bathtub_basin", PT, ("bathtub basin",)),
    # wall objects
    Category("painting", WO, ("picture", "poster", "artwork", "frame")),
    Category("mirror", WO, ()),
    Category("curtains", WO, ("curtain", "drapes")),
    Category("blinds", WO, ("blind",)),
    Category("wall_lamp", WO, ("wall lamp", "sconce")),
    # small objects
    Category("television", SO, ("tv", "television set")),
    Category("laptop", SO, ("notebook computer",)),
    Category("desktop_computer", SO, ("desktop", "computer", "pc")),
    Category("monitor", SO, ("screen", "computer monitor", "display")),
    Category("keyboard", SO, ("computer keyboard",)),
    Category("table_lamp", SO, ("desk lamp", "table lamp", "lamp")),
    Category("book", SO, ("books", "novel")),
    Category("pillow", SO, ("cushion",)),
    Category("vase", SO, ()),
    Category("bowl", SO, ()),
    Category("mug", SO, ()),
    Category("cup", SO, ("glass",)),
    Category("plate", SO, ("dish",)),
    Category("pot", SO, ("saucepan",)),
    Category("pan", SO, ("frying pan", "skillet")),
    Category("kettle", SO, ()),
    Category("box", SO, ("carton",)),
    Category("statue", SO, ("figurine", "sculpture")),
    Category("remote_control", SO, ("remote", "remote control")),
    Category("alarm_clock", SO, ("clock", "alarm clock")),
    Category("cell_phone", SO, ("phone", "smartphone", "cell phone")),
    Category("bottle", SO, ()),
    Category("wine_bottle", SO, ("wine bottle",)),
    Category("spray_bottle", SO, ("spray bottle",)),
    Category("soap_bottle", SO, ("soap bottle", "soap dispenser")),
    Category("candle", SO, ()),
    Category("tissue_box", SO, ("tissue box", "tissues")),
    Category("teddy_bear", SO, ("teddy bear", "teddy", "stuffed animal")),
    Category("watch", SO, ()),
    Category("key_chain", SO, ("key chain", "keys")),
    Category("credit_card", SO, ("credit card",)),
    Category("pen", SO, ()),
    Category("pencil", SO, ()),
    Category("cd", SO, ("compact disc",)),
    Category("newspaper", SO, ("magazine",)),
    Category("cloth", SO, ("rag",)),
    Category("towel", SO, ("bath towel",)),
    Category("hand_towel", SO, ("hand towel",)),
    Category("toilet_paper", SO, ("toilet paper", "toilet roll")),
    Category("paper_towel_roll", SO, ("paper towel roll", "paper towels")),
    Category("soap_bar", SO, ("soap bar", "soap")),
    Category("scrub_brush", SO, ("scrub brush",)),
    Category("plunger", SO, ()),
    Category("dish_sponge", SO, ("dish sponge", "sponge")),
    Category("salt_shaker", SO, ("salt shaker",)),
    Category("pepper_shaker", SO, ("pepper shaker",)),
    Category("fork", SO, ()),
    Category("knife", SO, ()),
    Category("butter_knife", SO, ("butter knife",)),
    Category("spoon", SO, ()),
    Category("spatula", SO, ()),
    Category("ladle", SO, ()),
    Category("microwave", SO, ("microwave oven",)),
    Category("toaster", SO, ()),
    Category("coffee_machine", SO, ("coffee machine", "coffee maker")),
    Category("apple", SO, ()),
    Category("bread", SO, ("loaf",)),
    Category("potato", SO, ()),
    Category("tomato", SO, ()),
    Category("egg", SO, ()),
    Category("lettuce", SO, ()),
    Category("aluminum_foil", SO, ("aluminum foil", "foil")),
    Category("watering_can", SO, ("watering can",)),
    Category("baseball_bat", SO, ("baseball bat",)),
    Category("basketball", SO, ("basket ball", "ball")),
    Category("tennis_racket", SO, ("tennis racket", "racket")),
    Category("dumbbell", SO, ()),
    Category("boots", SO, ("shoes",)),
    Category("garbage_bag", SO, ("garbage bag", "trash bag")),
    Category("decor", SO, ("decoration", "ornament", "table decor", "room decor")),
    # structure (room features)
    Category("floor", ST, ()),
    Category("wall", ST, ()),
    Category("ceiling", ST, ()),
    Category("window", ST, ()),
    Category("door", ST, ("doorway", "doorframe")),
    Category("light_switch", ST, ("light switch",)),
)
# fmt: on

BY_NAME: dict[str, Category] = {c.name: c for c in CATEGORIES}


def category(name: str) -> Category:
    """The canonical category ``name``; ``unknown`` gets an UNKNOWN super-category."""
    if name == UNKNOWN:
        return Category(UNKNOWN, SuperCategory.UNKNOWN)
    return BY_NAME[name]


def super_category(name: str) -> SuperCategory:
    return category(name).super if name in BY_NAME else SuperCategory.UNKNOWN


def is_structure(name: str) -> bool:
    return super_category(name) is ST


class RoomType(str, Enum):
    BEDROOM = "bedroom"
    LIVING_ROOM = "living_room"
    KITCHEN = "kitchen"
    BATHROOM = "bathroom"
    DINING_ROOM = "dining_room"
    OFFICE = "office"
    APARTMENT = "apartment"
    """A multi-purpose space: RoboTHOR apartments, studios, living-dining rooms."""
    OTHER = "other"


# -- source label tables -------------------------------------------------------

# AI2-THOR objectType (also ProcTHOR's asset database objectType) -> canonical.
# fmt: off
AI2THOR_LABELS: dict[str, str] = {
    "AlarmClock": "alarm_clock", "AluminumFoil": "aluminum_foil", "Apple": "apple",
    "ArmChair": "armchair", "BaseballBat": "baseball_bat", "BasketBall": "basketball",
    "Bathtub": "bathtub", "BathtubBasin": "bathtub_basin", "Bed": "bed", "Blinds": "blinds",
    "Book": "book", "Boots": "boots", "Bottle": "bottle", "Bowl": "bowl", "Box": "box",
    "Bread": "bread", "ButterKnife": "butter_knife", "CD": "cd", "Cabinet": "cabinet_door",
    "Candle": "candle", "Cart": "cart", "CellPhone": "cell_phone", "Chair": "chair",
    "Cloth": "cloth",
    "CoffeeMachine": "coffee_machine", "CoffeeTable": "coffee_table",
    "CounterTop": "counter_top", "CreditCard": "credit_card", "Cup": "cup",
    "Curtains": "curtains", "Desk": "desk", "DeskLamp": "table_lamp",
    "Desktop": "desktop_computer", "DiningTable": "dining_table", "DishSponge": "dish_sponge",
    "DogBed": "dog_bed", "Drawer": "drawer", "Dresser": "dresser", "Dumbbell": "dumbbell",
    "Egg": "egg", "Faucet": "faucet", "Floor": "floor", "FloorLamp": "floor_lamp",
    "Footstool": "ottoman", "Fork": "fork", "Fridge": "fridge", "GarbageBag": "garbage_bag",
    "GarbageCan": "garbage_can", "HandTowel": "hand_towel", "HandTowelHolder": "towel_holder",
    "HousePlant": "house_plant", "Kettle": "kettle", "KeyChain": "key_chain", "Knife": "knife",
    "Ladle": "ladle", "Laptop": "laptop", "LaundryHamper": "laundry_hamper",
    "Lettuce": "lettuce", "LightSwitch": "light_switch", "Microwave": "microwave",
    "Mirror": "mirror", "Mug": "mug", "Newspaper": "newspaper", "Ottoman": "ottoman",
    "Painting": "painting", "Pan": "pan", "PaperTowelRoll": "paper_towel_roll",
    "Pen": "pen", "Pencil": "pencil", "PepperShaker": "pepper_shaker", "Pillow": "pillow",
    "Plate": "plate", "Plunger": "plunger", "Poster": "painting", "Pot": "pot",
    "Potato": "potato", "RemoteControl": "remote_control", "RoomDecor": "decor",
    "Safe": "safe", "SaltShaker": "salt_shaker", "ScrubBrush": "scrub_brush",
    "Shelf": "shelf", "ShelvingUnit": "shelving_unit", "ShowerCurtain": "shower",
    "ShowerDoor": "shower", "ShowerGlass": "shower", "ShowerHead": "shower",
    "SideTable": "side_table",
    "Sink": "sink", "SinkBasin": "sink_basin", "SoapBar": "soap_bar",
    "SoapBottle": "soap_bottle", "Sofa": "sofa", "Spatula": "spatula", "Spoon": "spoon",
    "SprayBottle": "spray_bottle", "Statue": "statue", "Stool": "stool",
    "StoveBurner": "stove", "StoveKnob": "stove_knob", "TVStand": "tv_stand",
    "TableTopDecor": "decor", "TeddyBear": "teddy_bear", "Television": "television",
    "TennisRacket": "tennis_racket", "TissueBox": "tissue_box", "Toaster": "toaster",
    "Toilet": "toilet", "ToiletPaper": "toilet_paper",
    "ToiletPaperHanger": "toilet_paper_hanger", "Tomato": "tomato", "Towel": "towel",
    "TowelHolder": "towel_holder", "VacuumCleaner": "vacuum_cleaner", "Vase": "vase",
    "Watch": "watch", "WateringCan": "watering_can", "Window": "window",
    "WineBottle": "wine_bottle",
    # ProcTHOR / RoboTHOR structural types
    "Doorway": "door", "Doorframe": "door", "Door": "door", "Wall": "wall", "Ceiling": "ceiling",
}

# 3D-FUTURE "category" (model_info.json) and lower-cased super-categories -> canonical.
FUTURE3D_LABELS: dict[str, str] = {
    "children cabinet": "cabinet", "nightstand": "side_table",
    "bookcase / jewelry armoire": "shelving_unit", "wardrobe": "wardrobe",
    "coffee table": "coffee_table", "corner/side table": "side_table",
    "sideboard / side cabinet / console table": "cabinet",
    "sideboard / side cabinet / console": "cabinet", "wine cabinet": "cabinet",
    "tv stand": "tv_stand", "drawer chest / corner cabinet": "dresser", "shelf": "shelving_unit",
    "round end table": "side_table", "king-size bed": "bed", "bunk bed": "bed",
    "bed frame": "bed", "single bed": "bed", "kids bed": "bed", "dining chair": "chair",
    "lounge chair / cafe chair / office chair": "chair",
    "lounge chair / book-chair / computer chair": "chair", "dressing chair": "chair",
    "classic chinese chair": "chair", "barstool": "stool", "dressing table": "dressing_table",
    "dining table": "dining_table", "desk": "desk", "three-seat / multi-seat sofa": "sofa",
    "three-seat / multi-person sofa": "sofa", "armchair": "armchair",
    "loveseat sofa": "sofa", "l-shaped sofa": "sofa", "lazy sofa": "sofa",
    "chaise longue sofa": "sofa", "footstool / sofastool / bed end stool / stool": "ottoman",
    "pendant lamp": "ceiling_lamp", "ceiling lamp": "ceiling_lamp", "floor lamp": "floor_lamp",
    "wall lamp": "wall_lamp", "table lamp": "table_lamp", "tea table": "coffee_table",
    "cabinet": "cabinet", "sofa": "sofa", "chair": "chair", "table": "dining_table",
    "bed": "bed", "pier/stool": "ottoman", "lighting": "ceiling_lamp",
    "cabinet/shelf/desk": "cabinet",
}

# 3D-FRONT room "type" -> room type.
FRONT3D_ROOM_TYPES: dict[str, RoomType] = {
    "bedroom": RoomType.BEDROOM, "masterbedroom": RoomType.BEDROOM,
    "secondbedroom": RoomType.BEDROOM, "kidsroom": RoomType.BEDROOM,
    "elderlyroom": RoomType.BEDROOM, "nannyroom": RoomType.BEDROOM,
    "livingroom": RoomType.LIVING_ROOM, "livingdiningroom": RoomType.APARTMENT,
    "diningroom": RoomType.DINING_ROOM, "kitchen": RoomType.KITCHEN,
    "bathroom": RoomType.BATHROOM, "secondbathroom": RoomType.BATHROOM,
    "masterbathroom": RoomType.BATHROOM, "library": RoomType.OFFICE,
    "studyroom": RoomType.OFFICE,
}

PROCTHOR_ROOM_TYPES: dict[str, RoomType] = {
    "Bedroom": RoomType.BEDROOM, "LivingRoom": RoomType.LIVING_ROOM,
    "Kitchen": RoomType.KITCHEN, "Bathroom": RoomType.BATHROOM,
}
# fmt: on


def _norm(label: str) -> str:
    return re.sub(r"\s+", " ", label.strip().lower())


@dataclass
class LabelMapper:
    """Maps one source's labels to canonical names and counts what it cannot map."""

    table: dict[str, str]
    case_insensitive: bool = False
    unknown: Counter[str] = field(default_factory=Counter)
    mapped: Counter[str] = field(default_factory=Counter)

    def __post_init__(self) -> None:
        if self.case_insensitive:
            self.table = {_norm(k): v for k, v in self.table.items()}

    def __call__(self, label: str | None) -> str:
        key = "" if label is None else (_norm(label) if self.case_insensitive else label)
        name = self.table.get(key)
        if name is None:
            self.unknown[label if label else "<missing>"] += 1
            return UNKNOWN
        self.mapped[key] += 1
        return name


MOUNTED_CATEGORIES = frozenset(
    {"television", "microwave", "towel_holder", "toilet_paper_hanger", "shower"}
)
"""Besides the wall objects (paintings, mirrors, curtains, blinds, wall lamps), what the
sources hang on walls: televisions (ProcTHOR: 164 of them), over-the-range microwaves
(AI2-THOR kitchens), towel rails and paper holders, shower heads."""


def hangs_on_walls(category: str) -> bool:
    """Whether objects of ``category`` may hang on a wall (a wall object, or one of
    :data:`MOUNTED_CATEGORIES`)."""
    cat = BY_NAME.get(category)
    return (cat is not None and cat.super is SuperCategory.WALL_OBJECT) or (
        category in MOUNTED_CATEGORIES
    )


TURN_FREE = frozenset({"house_plant", "floor_lamp", "garbage_can"})
"""Floor objects whose turn means nothing (a round pot, a lamp's round foot, a bin): the
training rooms turn them any way, so whether one stands by a wall is read from its
footprint's distance to the wall, not from a face parallel to it. In the training
bedrooms, within 0.3 m of a wall (footprint): plants 42 of 42, floor lamps 51 of 52, bins
60 of 65; with a face against one (0.15 m, 15 degrees), as the statistics counted before:
11 of 42, 6 of 52 and 52 of 62."""
WINDOW_DRESSINGS = frozenset({"curtains", "blinds"})
"""Wall objects that hang at a window (placement puts one at each window it can, a text's
"curtains on the windows" gives one per window), never relative to another object."""
SEATS = frozenset({"chair", "stool"})
"""Seats pulled up to a table or desk (:data:`SEATED_AT`)."""
SEATED_AT = frozenset({"dining_table", "desk", "dressing_table"})
"""Furniture sat at: where it stands depends on how many seats it has. The curated training
rooms' dining tables stand against a wall 133 times of 138 with no chair at them (92 in a
corner), 36 of 89 with one, 13 of 47 with two, 7 of 30 with three and 0 of 91 with four or
more (every room type)."""
HANGS_OVER = frozenset({"painting", "mirror", "wall_lamp"})
"""Wall objects that hang over or beside the floor object they relate to, on the wall
behind it (a painting above the bed or sofa, a mirror above the dresser, a wall lamp
beside the bed): that object stands against a wall (the training rooms' pairs did; a
television relates to the sofa across the room instead)."""


def _check_tables() -> None:
    for table in (AI2THOR_LABELS, FUTURE3D_LABELS):
        bad = sorted(set(table.values()) - set(BY_NAME))
        if bad:  # a programming error in this module, caught by the test suite on import
            raise AssertionError(f"label tables name unknown categories: {bad}")


_check_tables()
