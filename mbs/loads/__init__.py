"""Rotor loads: what every joint carries, the hub loads, their harmonics per revolution, and
power as an engine sees it."""
