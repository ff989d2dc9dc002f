"""Locomotion toward a light in PyBullet: the lower agent, the body's pose, memo tables, exact
trials and the Gymnasium envs, registered here (by string entry points, so PyBullet loads only
when an env is made)."""

import gymnasium

TRIAL_STEPS = 30
"""The default trial's length in posture steps: :class:`qdsega.task.TaskConfig`'s
``trial_steps``, written here too (a test holds them equal) so that registering the envs does
not compile the task's rules. ``gym.make`` cuts episodes there (``max_episode_steps``)."""

CONTROLS_PER_POSTURE = 12
"""Steps of :class:`qdsega.locomotion.joint_env.JointLocomotionEnv` per posture step of the
lower agent (-): 12 steps of 10 physics steps each for the shipped bodies' 0.5 s posture steps
(24 Hz), a whole number of physics steps for every derived step duration (a multiple of 0.05 s
at 240 Hz). Its episodes last a trial's physics time."""

ENV_ID = "qdsega/Locomotion-v0"
"""The Gymnasium id of :class:`qdsega.locomotion.env.LocomotionEnv`."""

gymnasium.register(
    id=ENV_ID, entry_point="qdsega.locomotion.env:LocomotionEnv", max_episode_steps=TRIAL_STEPS
)

TABLE_ENV_ID = "qdsega/TableLocomotion-v0"
"""The Gymnasium id of :class:`qdsega.locomotion.table_env.TableLocomotionEnv`: the same task in
a table model (the MSM or a memo table), for learners other than QDSEGA at table speed."""

gymnasium.register(
    id=TABLE_ENV_ID,
    entry_point="qdsega.locomotion.table_env:TableLocomotionEnv",
    max_episode_steps=TRIAL_STEPS,
)

JOINT_ENV_ID = "qdsega/JointLocomotion-v0"
"""The Gymnasium id of :class:`qdsega.locomotion.joint_env.JointLocomotionEnv`: the same task
under continuous control (joint targets), for PPO, SAC and the like."""

gymnasium.register(
    id=JOINT_ENV_ID,
    entry_point="qdsega.locomotion.joint_env:JointLocomotionEnv",
    max_episode_steps=TRIAL_STEPS * CONTROLS_PER_POSTURE,
)
