"""Reference gaits a learnt policy is measured against: classic gaits, a CPG, and the CPG tuned
by CMA-ES in exact physics (with its shipped results in ``references/``)."""
