"""Scene assembly: placing a hierarchy with the layout model, collision-free and at rest."""
