"""Generator families; importing this package registers every generator."""

from pair2scene.assets.generators import (  # noqa: F401
    fixtures,
    household,
    seating,
    storage,
    tables,
    tableware,
)
