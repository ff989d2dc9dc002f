"""Shipped unit types, one folder each; installed as ``qdsega.units`` (data only)."""
