"""Metrics of generated scenes."""
