"""Shipped formations, one YAML file each; installed as ``qdsega.assemblies`` (data only)."""
