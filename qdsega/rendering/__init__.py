"""Rendering: off-screen videos of a formation executing postures."""
