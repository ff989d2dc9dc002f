"""Locomotion toward a light in PyBullet: the lower agent, the body's pose, memo tables, exact
trials and the Gymnasium envs, registered here (by string entry points, so PyBullet loads only
when an env is made)."""

import gymnasium

ENV_ID = "qdsega/Locomotion-v0"
"""The Gymnasium id of :class:`qdsega.locomotion.env.LocomotionEnv`."""

gymnasium.register(id=ENV_ID, entry_point="qdsega.locomotion.env:LocomotionEnv")

TABLE_ENV_ID = "qdsega/TableLocomotion-v0"
"""The Gymnasium id of :class:`qdsega.locomotion.table_env.TableLocomotionEnv`: the same task in
a table model (the MSM or a memo table), for learners other than QDSEGA at table speed."""

gymnasium.register(id=TABLE_ENV_ID, entry_point="qdsega.locomotion.table_env:TableLocomotionEnv")
