"""Flexible bodies: bodies whose sections move with modal coordinates on top of their frame."""
