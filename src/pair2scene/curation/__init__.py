"""3D-Pairs curation: scenes -> validated relation tuples and statistics."""
