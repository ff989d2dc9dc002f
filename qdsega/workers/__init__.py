"""Workers for simulations: spawned processes, or Ray actors on this machine or a cluster."""
