"""Shipped worlds, one YAML file each; installed as ``qdsega.worlds`` (data only)."""
