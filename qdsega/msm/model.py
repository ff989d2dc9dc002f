"""The Minimal Simulation Model (section 4.1.2, eqs. (7)-(16)) as a posture-transition table.

Per side ``s`` (left, right) and per step, with ``n_ij`` the number of that side's legs going
from state ``i`` to state ``j``:

* drive ``f_drv = u (n_12 - n_21)`` (7): a leg pushed back while down propels the body;
* resistance ``f_res = v (n_11 + n_22)`` (8): a leg that stays down without moving drags;
* net side force ``F^s`` (9): 0 if ``|f_drv| <= f_res``, else ``f_drv`` shrunk by ``f_res``;
* ``F = F^l + F^r`` (10), ``M = F^r - F^l`` (11), ``du = c_u F`` (12), ``dtheta = c_theta M``
  (13); the pose moves ``du`` along the heading at the start of the step (14)-(16).

Every other leg transition (lifting, landing, swinging in the air) exerts no force.

Choices the paper leaves open (the defaults of :class:`MSMParameters`):

* ``u = 1``, ``v = 0.5``: a still, planted leg drags half as hard as a stroking leg pushes.
  With ``v < u`` pushing legs beat standing ones, yet two standing legs stall one stroke, so a
  gait that leaves legs idle on the ground loses; ``u`` and ``v`` are commensurate, so headings
  stay on a lattice.
* ``c_u = 0.02`` m per unit force: legged12's best gait makes 4 force units a step, 8 cm.
  Eq. (17) multiplies metres by 100, so rewards are a few units a step: the scale at which
  eq. (18)'s schedule (T = 408 at the first trial, 1 at trial 3000, 0.001 at trial 6500)
  explores for the first third of a generation and is greedy after. With 10x larger steps,
  rewards swamp the temperature early and learning locks onto the first gait it meets.
* ``c_theta = 0.05`` rad per unit moment: one side striding (2 units) while the other stands
  turns the robot 0.1 rad (5.7 deg) a step; facing a light 60 deg to the side costs about ten
  steps of a 30-step trial, so turning is a skill to learn, not a free move.
* The light (the formation's ``light``; 50 m straight ahead for the paper's bodies): "far
  enough from the start position" (4.1.1). A trial covers at most 2.4 m, so the bearing to
  the light moves by under 3 deg: walking straight is optimal and the reward (eq. 17) is the
  forward progress. The turn experiment puts it 60 deg to the left at the same distance,
  outside the +-45 deg field of the exterior bins.
* Failure (the lower agent cannot reach the commanded posture: the robot falls) when a side
  has fewer than ``min_down_per_side`` (default 1) legs down in the commanded posture: a side
  with every leg lifted has no support, and lifting all legs at once always falls. Stricter
  rules (half the legs of a side) made 57 % of random postures fall and, in trials, the
  learner did worse, not better.
* The start posture has every leg in ``start_state`` (default 2: back and down, the end of
  a stroke: the robot stands, no leg ready to push); joints that belong to no leg start (and
  are ignored) at level 0. From state 1 (forward and down) every leg can stroke at once on
  the first step, 12 force units that no gait can repeat, 14 % of legged12's 20-step
  optimum (86 units; 10 % of 125 at 30 steps): the best gait entered plainly then reaches
  only 0.907 (0.944 at 30 steps) of the optimum, and "0.95 of the optimum" would measure
  whether that one-off burst was learnt rather than the gait. From state 2 the optimum is
  the gait: the best gait entered plainly reaches 0.961 (20 steps) and 0.966 (30 steps).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from qdsega.agent.model import Transitions
from qdsega.msm.legs import LegLayout


@dataclass(frozen=True)
class MSMParameters:
    """Constants of the Minimal Simulation Model (module docstring: why these values).

    Attributes:
        u: drive of one leg stroke, eq. (7) (force units).
        v: resistance of one still, planted leg, eq. (8) (force units).
        c_u: forward displacement per unit of total force, eq. (12) (m).
        c_theta: heading change per unit of moment, eq. (13) (rad).
        min_down_per_side: legs each side must keep down in the commanded posture, else the
            robot falls.
        start_state: leg state 1..4 of every leg in the start posture.
    """

    u: float = 1.0
    v: float = 0.5
    c_u: float = 0.02
    c_theta: float = 0.05
    min_down_per_side: int = 1
    start_state: int = 2

    def __post_init__(self) -> None:
        if not self.u > 0:
            raise ValueError(f"u must be positive, got {self.u}")
        if not self.v >= 0:
            raise ValueError(f"v must not be negative, got {self.v}")
        if not self.c_u > 0 or not self.c_theta >= 0:
            raise ValueError("c_u must be positive and c_theta non-negative")
        if self.min_down_per_side < 0:
            raise ValueError(f"min_down_per_side must be >= 0, got {self.min_down_per_side}")
        if self.start_state not in (1, 2, 3, 4):
            raise ValueError(f"start_state must be a leg state 1..4, got {self.start_state}")


def side_force(f_drv: np.ndarray, f_res: np.ndarray) -> np.ndarray:
    """Eq. (9): net force of one side from its drive and (non-negative) resistance."""
    f_drv = np.asarray(f_drv, dtype=np.float64)
    f_res = np.asarray(f_res, dtype=np.float64)
    return np.where(
        np.abs(f_drv) <= f_res, 0.0, np.where(f_drv > f_res, f_drv - f_res, f_drv + f_res)
    )


class MinimalSimulationModel:
    """The MSM of a legged body, as a :class:`qdsega.agent.model.TransitionProvider`.

    Args:
        legs: the body's legs.
        params: the model's constants.
    """

    def __init__(self, *, legs: LegLayout, params: MSMParameters) -> None:
        self.legs = legs
        self.params = params
        n_left, n_right = legs.legs_per_side()
        if min(n_left, n_right) < params.min_down_per_side:
            raise ValueError(
                f"a side has fewer legs ({min(n_left, n_right)}) than min_down_per_side "
                f"({params.min_down_per_side}): the robot could never stand"
            )
        start = self.start_posture()
        if self.falls(start[None, :])[0]:
            raise ValueError(f"the start posture (all legs in state {params.start_state}) falls")

    @property
    def n_joints(self) -> int:
        return self.legs.n_joints

    def start_posture(self) -> np.ndarray:
        """Every leg in ``start_state``, other joints at level 0, shape (J,)."""
        states = np.full(self.legs.n_legs, self.params.start_state)
        return self.legs.posture(states, base=np.zeros(self.n_joints, dtype=np.int64))

    def falls(self, postures: np.ndarray) -> np.ndarray:
        """Whether commanding each posture (n, J) makes the robot fall, shape (n,)."""
        down = self.legs.states(postures) <= 2
        right = np.asarray(self.legs.right)
        k = self.params.min_down_per_side
        return (down[..., ~right].sum(axis=-1) < k) | (down[..., right].sum(axis=-1) < k)

    def side_forces(
        self, from_states: np.ndarray, to_states: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Eqs. (7)-(9): leg states (..., L) before and after, broadcast against each other
        -> (F^l, F^r), each of the broadcast shape without the leg axis."""
        a, b = np.asarray(from_states), np.asarray(to_states)
        drive = ((a == 1) & (b == 2)).astype(np.int64) - ((a == 2) & (b == 1))
        still = ((a == 1) & (b == 1)) | ((a == 2) & (b == 2))
        right = np.asarray(self.legs.right)
        forces = []
        for mask in (~right, right):
            f_drv = self.params.u * drive[..., mask].sum(axis=-1)
            f_res = self.params.v * still[..., mask].sum(axis=-1)
            forces.append(side_force(f_drv, f_res))
        return forces[0], forces[1]

    def transitions(self, from_postures: np.ndarray, to_postures: np.ndarray) -> Transitions:
        """Eqs. (7)-(13) for every (from, to) posture pair; ``dy`` is always 0."""
        from_states = self.legs.states(np.atleast_2d(from_postures))[:, None, :]
        to_postures = np.atleast_2d(to_postures)
        dx, dtheta, failed = self._moves(from_states, to_postures[None, :, :])
        return Transitions(dx=dx, dy=np.zeros(dx.shape), dtheta=dtheta, failed=failed)

    def moves(
        self, from_postures: np.ndarray, to_postures: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Eqs. (7)-(13) pair by pair: postures (..., J) before and after, of one shape ->
        body-frame ``dx`` (m), ``dtheta`` (rad) and ``failed``, each of shape (...)."""
        from_postures, to_postures = np.asarray(from_postures), np.asarray(to_postures)
        if from_postures.shape != to_postures.shape:
            raise ValueError(f"shapes differ: {from_postures.shape} and {to_postures.shape}")
        return self._moves(self.legs.states(from_postures), to_postures)

    def _moves(
        self, from_states: np.ndarray, to_postures: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        f_left, f_right = self.side_forces(from_states, self.legs.states(to_postures))
        failed = np.broadcast_to(self.falls(to_postures), f_left.shape).copy()
        moving = ~failed
        dx = np.where(moving, self.params.c_u * (f_left + f_right), 0.0)
        dtheta = np.where(moving, self.params.c_theta * (f_right - f_left), 0.0)
        return dx, dtheta, failed
