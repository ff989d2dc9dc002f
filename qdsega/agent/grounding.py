"""A transition table grounded in exact trials: measured moves corrected by observed ones.

A table measures each transition ``i -> j`` once, from a settled start in ``i``. A body whose
step depends on more than its posture (a snake's momentum, the friction it has built up)
moves differently inside a trial: there the move ``i -> j`` depends mostly on the posture
``h`` the body came from. :class:`GroundedTransitions` keeps every move that exact trials
went through, and answers Dyna-style (the learner plans on a model that is corrected where its
policies actually go), the most specific knowledge first:

0. where a walk from the start of a trial follows the commands of a remembered trial, that
   trial's move (:class:`qdsega.agent.model.Paths`): physics is deterministic, so the same
   commands from the same start move the robot the same way, whatever other trials saw;
1. the mean move of the latest trial that went ``i -> j`` entered from ``h`` (or at the start
   of a trial: a context row of the table, :class:`qdsega.agent.model.Transitions`);
2. else the mean of the moves observed for ``i -> j`` in any context;
3. else the base table's measurement, less the root-mean-square gap (m) between the base's
   forward moves and the observed ones (a lower confidence bound: among many unobserved
   transitions the learner would pick those the base overrates, and predict a gait that
   exact physics then does not walk; where the base is right, as for legged bodies, the gap
   and the correction are small). An explorer asks for an upper bound instead
   (``confidence`` > 0: the measurement plus that many gaps), so that what it tries is what
   the table may underrate.

In its context the latest trial's mean, not the mean of all: the physics is deterministic,
and what a move does there still depends on the history before ``h``, which is that of the
policy that went there last. The exact trials of a generation are observed exploring ones
first, the greedy one last, so a greedy policy the learner keeps is predicted as its last
replay went. A transition observed to fail in its context fails there (a gait that slips a
little each cycle falls after a few cycles, in the same context as the cycles it survived);
in any context, one observed to fail more often than not fails.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from qdsega.agent.model import Paths, TransitionProvider, Transitions
from qdsega.agent.policy import Rollout
from qdsega.task import relative_move

_SUMS = 5  # dx (m), dy (m), dtheta (rad) (summed, or latest in context); moves; failures


class GroundedTransitions:
    """A :class:`qdsega.agent.model.TransitionProvider`: ``base`` corrected by observations.

    Args:
        base: the table of measured transitions.
    """

    def __init__(self, *, base: TransitionProvider) -> None:
        self.base = base
        self._plain: dict[bytes, np.ndarray] = {}  # i + j -> sums
        self._context: dict[bytes, dict[bytes, np.ndarray]] = {}  # h + i -> {j -> latest}
        self._start = np.full(self.n_joints, -1, dtype=np.int64).tobytes()  # h of a start
        self._base_dx: dict[bytes, float] = {}  # i + j -> the base's forward move (m)
        # Remembered trials: node 0 is a trial's start; each node is one command's outcome.
        self._children: list[dict[bytes, int]] = [{}]  # node -> {target -> node}
        self._moves: list[np.ndarray] = [np.zeros(4)]  # node -> dx, dy, dtheta, failed
        self._parent: list[int] = [-1]
        self._target: list[bytes] = [b""]

    @property
    def n_joints(self) -> int:
        return self.base.n_joints

    def start_posture(self) -> np.ndarray:
        return self.base.start_posture()

    def __len__(self) -> int:
        """Transitions observed at least once (in any context)."""
        return len(self._plain)

    def transitions(
        self, from_postures: np.ndarray, to_postures: np.ndarray, *, confidence: float = -1.0
    ) -> Transitions:
        """The base table's outcomes, corrected by what was observed (module docstring); an
        unobserved forward move is the base's plus ``confidence`` times :meth:`base_gap_m`."""
        sources = np.asarray(from_postures, dtype=np.int64)
        targets = np.asarray(to_postures, dtype=np.int64)
        base = self.base.transitions(sources, targets)
        if not self._plain:
            return base
        keys = [t.tobytes() for t in targets]
        gap = self.base_gap_m()
        unobserved = Transitions(
            dx=np.asarray(base.dx, dtype=np.float64) + confidence * gap,
            dy=base.dy,
            dtheta=base.dtheta,
            failed=base.failed,
        )
        plain = _corrected(
            unobserved,
            [{k: self._plain.get(s.tobytes() + k) for k in keys} for s in sources],
            True,
        )
        context = np.full((len(sources) + 1, len(sources)), -1, dtype=np.int64)
        rows: list[dict[bytes, np.ndarray | None]] = []
        base_rows: list[int] = []
        for h, previous in enumerate([*(s.tobytes() for s in sources), self._start]):
            for i, source in enumerate(sources):
                seen = self._context.get(previous + source.tobytes())
                if seen is None or not any(k in seen for k in keys):
                    continue
                context[h, i] = len(rows)
                rows.append({k: seen.get(k) for k in keys})
                base_rows.append(i)
        paths = self._paths(keys)
        if not rows:
            return replace(plain, paths=paths)
        in_context = _corrected(
            Transitions(
                dx=plain.dx[base_rows],
                dy=plain.dy[base_rows],
                dtheta=plain.dtheta[base_rows],
                failed=plain.failed[base_rows],
            ),
            rows,
            False,
        )
        return Transitions(
            dx=plain.dx,
            dy=plain.dy,
            dtheta=plain.dtheta,
            failed=plain.failed,
            context=context,
            in_context=in_context,
            paths=paths,
        )

    def _paths(self, keys: list[bytes]) -> Paths:
        """The remembered trials that command only postures among ``keys`` (target columns)
        from their start, as a tree over those columns."""
        column = {k: c for c, k in enumerate(keys)}
        kept = [0]  # old node ids, in new order
        child = [np.full(len(keys), -1, dtype=np.int64)]
        new = 0
        while new < len(kept):  # breadth first from the start
            for target, old in self._children[kept[new]].items():
                c = column.get(target)
                if c is None:
                    continue
                child[new][c] = len(kept)
                kept.append(old)
                child.append(np.full(len(keys), -1, dtype=np.int64))
            new += 1
        moves = np.array([self._moves[k] for k in kept])
        return Paths(
            child=np.array(child),
            dx=moves[:, 0],
            dy=moves[:, 1],
            dtheta=moves[:, 2],
            failed=moves[:, 3] > 0.5,
        )

    def base_gap_m(self) -> float:
        """Root-mean-square difference between the observed mean forward move and the base's
        measurement, over the transitions observed to move (m). Summed in key order, not in
        the order they were observed, so that a resumed run (whose observations come back
        sorted) gets the same value bit for bit."""
        gaps = []
        for key in sorted(self._plain):
            sums = self._plain[key]
            if sums[3] == 0:
                continue
            if key not in self._base_dx:
                source, target = np.frombuffer(key, dtype=np.int64).reshape(2, -1)
                self._base_dx[key] = float(
                    self.base.transitions(source[None], target[None]).dx[0, 0]
                )
            gaps.append(sums[0] / sums[3] - self._base_dx[key])
        return float(np.sqrt(np.mean(np.square(gaps)))) if gaps else 0.0

    def observe(self, trial: Rollout, start: np.ndarray) -> int:
        """Record the moves of an exact trial that started in posture ``start`` (J,); returns
        the commands it observed."""
        reached = trial.reached_postures(start)
        trial_sums: dict[tuple[bytes, bytes], np.ndarray] = {}  # this trial's, in context
        targets = list(reached[1:]) + ([trial.postures[-1]] if trial.failed else [])
        for t, target in enumerate(targets):
            if t < len(reached) - 1:
                move = relative_move(tuple(trial.poses[t]), tuple(trial.poses[t + 1]))
                outcome = np.array([*move, 1.0, 0.0])
            else:  # the failed command
                outcome = np.array([0.0, 0.0, 0.0, 0.0, 1.0])
            source = reached[t].tobytes()
            self._plain.setdefault(source + target.tobytes(), np.zeros(_SUMS))[:] += outcome
            previous = reached[t - 1].tobytes() if t > 0 else self._start
            key = (previous + source, target.tobytes())
            trial_sums.setdefault(key, np.zeros(_SUMS))[:] += outcome
        for (pair, target), sums in trial_sums.items():
            latest = self._context.setdefault(pair, {}).setdefault(target, np.zeros(_SUMS))
            latest[3:] += sums[3:]
            if sums[3]:
                latest[:3] = sums[:3] / sums[3]
        self._remember(targets, trial)
        return len(targets)

    def _remember(self, targets: list[np.ndarray], trial: Rollout) -> None:
        """Add the trial's commands and moves to the tree of remembered trials."""
        node = 0
        for t, target in enumerate(targets):
            move = np.zeros(4)
            if trial.failed and t == len(targets) - 1:
                move[3] = 1.0
            else:
                move[:3] = relative_move(tuple(trial.poses[t]), tuple(trial.poses[t + 1]))
            node = self._add_node(node, target.tobytes(), move)

    def _add_node(self, parent: int, target: bytes, move: np.ndarray) -> int:
        """The child of ``parent`` for ``target``, made if new; its move set to ``move``."""
        node = self._children[parent].get(target)
        if node is None:
            node = len(self._moves)
            self._children[parent][target] = node
            self._children.append({})
            self._moves.append(move)
            self._parent.append(parent)
            self._target.append(target)
        else:
            self._moves[node] = move
        return node

    def state(self) -> dict[str, np.ndarray]:
        """The observations as arrays (for a checkpoint): ``plain_keys`` (n, 2J) levels of
        ``i, j`` and ``plain_sums`` (n, 5): summed dx (m), dy (m), dtheta (rad), moves,
        failures; ``context_keys`` (c, 3J) levels of ``h, i, j`` (``h`` all -1: the start of
        a trial) and ``context_sums`` (c, 5): the latest trial's mean dx, dy, dtheta; all moves
        and failures; the remembered trials' nodes after the start, in the order they were
        made: ``path_parents`` (N,), ``path_targets`` (N, J) levels commanded,
        ``path_moves`` (N, 4) dx (m), dy (m), dtheta (rad), failed."""
        triples = {
            pair + target: sums
            for pair, seen in self._context.items()
            for target, sums in seen.items()
        }
        j = self.n_joints
        targets = [np.frombuffer(t, dtype=np.int64) for t in self._target[1:]]
        return {
            **_arrays("plain", self._plain, 2 * j),
            **_arrays("context", triples, 3 * j),
            "path_parents": np.array(self._parent[1:], dtype=np.int64),
            "path_targets": np.array(targets, dtype=np.int64).reshape(-1, j),
            "path_moves": np.array(self._moves[1:], dtype=np.float64).reshape(-1, 4),
        }

    def restore(self, state: dict[str, np.ndarray]) -> None:
        """Replace the observations with those of :meth:`state`.

        Raises:
            ValueError: the arrays do not fit this body.
        """
        j = self.n_joints
        plain = _entries(state, "plain", 2 * j)
        triples = _entries(state, "context", 3 * j)
        self._plain = plain
        self._context = {}
        width = 2 * j * 8  # bytes of h + i
        for key, sums in triples.items():
            self._context.setdefault(key[:width], {})[key[width:]] = sums
        parents, targets, moves = (state[k] for k in ("path_parents", "path_targets", "path_moves"))
        n = len(parents)
        if targets.shape != (n, j) or moves.shape != (n, 4) or np.any(parents >= 1 + np.arange(n)):
            raise ValueError(
                f"remembered trials {targets.shape}, {moves.shape} do not fit this body"
            )
        self._children, self._moves, self._parent, self._target = [{}], [np.zeros(4)], [-1], [b""]
        for parent, target, move in zip(parents, targets, moves, strict=True):
            self._add_node(int(parent), target.astype(np.int64).tobytes(), move.astype(np.float64))


def _corrected(
    table: Transitions, rows: list[dict[bytes, np.ndarray | None]], summed: bool
) -> Transitions:
    """``table`` (n, m) with each observed entry (``rows[i][key of target j]``) replaced by
    the observed move (``summed``: the mean of the summed moves; else the latest); ``rows``
    lists the targets' keys in column order. An entry fails where most of its observations
    failed (``summed``), else where any did."""
    dx, dy, dtheta = (np.array(a, dtype=np.float64) for a in (table.dx, table.dy, table.dtheta))
    failed = np.array(table.failed, dtype=np.bool_)
    for i, row in enumerate(rows):
        for j, sums in enumerate(row.values()):
            if sums is None:
                continue
            moves, failures = sums[3], sums[4]
            failed[i, j] = failures > moves if summed else failures > 0
            if moves > 0:
                dx[i, j], dy[i, j], dtheta[i, j] = sums[:3] / moves if summed else sums[:3]
    return Transitions(dx=dx, dy=dy, dtheta=dtheta, failed=failed)


def _arrays(name: str, entries: dict[bytes, np.ndarray], width: int) -> dict[str, np.ndarray]:
    keys = sorted(entries)
    levels = np.array([np.frombuffer(k, dtype=np.int64) for k in keys], dtype=np.int64)
    sums = np.array([entries[k] for k in keys], dtype=np.float64)
    return {
        f"{name}_keys": levels.reshape(len(keys), width),
        f"{name}_sums": sums.reshape(len(keys), _SUMS),
    }


def _entries(state: dict[str, np.ndarray], name: str, width: int) -> dict[bytes, np.ndarray]:
    keys, sums = state[f"{name}_keys"], state[f"{name}_sums"]
    if keys.shape[1:] != (width,) or sums.shape != (len(keys), _SUMS):
        raise ValueError(f"observations {keys.shape}, {sums.shape} do not fit this body")
    return {
        k.astype(np.int64).tobytes(): s.astype(np.float64).copy()
        for k, s in zip(keys, sums, strict=True)
    }
