"""Reference gaits computed at the default budget, shipped with the package (JSON)."""
