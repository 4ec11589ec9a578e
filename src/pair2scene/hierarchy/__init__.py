"""Scene hierarchies: support and functional trees, from statistics or from text."""
