"""Adaptation after a body changes: a repertoire of diverse gaits built before (MAP-Elites),
and trial and error on the changed body guided by it (Cully et al. 2015, IT&E)."""
