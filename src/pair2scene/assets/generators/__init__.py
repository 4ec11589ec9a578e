"""Generator families; importing this package registers every generator."""

from pair2scene.assets.generators import (  # noqa: F401
    appliances,
    beds,
    fixtures,
    food,
    household,
    lighting,
    seating,
    storage,
    tables,
    tableware,
)
