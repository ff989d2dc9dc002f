"""QDSEGA: Q-learning with dynamic structuring of the exploration space by a GA (section 3)."""
