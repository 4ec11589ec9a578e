"""pair2scene: dense, physically plausible 3D indoor scenes from pairwise placement rules."""

__version__ = "0.1.0"
