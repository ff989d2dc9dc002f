"""``qdsega reform``: the formation a body's units should take, in a world, and how to get there.

1. The candidates (:mod:`qdsega.reform.candidates`) are written as formation files and checked
   as ``qdsega assemble`` checks a body (the reach check included) and as ``train`` checks a
   body in its world; one that fails is dropped with its reason.
2. **Screening**: each candidate learns the first generations of its own run (its own preset,
   memo mode, the screening budget of generations), and its best greedy policy so far in exact
   physics is its estimate. Later rounds move on from the best few.
3. **Learning**: the best candidates, and always the body as it is, learn their runs to the
   end, and each is evaluated in exact physics. Given the intact body's repertoire, the body
   as it is is also adapted from it (``qdsega adapt``).
4. The farthest in exact physics wins; a re-formation is proposed only where it beats the body
   as it is, relearnt and adapted.

Everything lives in the output folder, and every step is kept as it finishes (run folders
resume, an adaptation is kept), so a reform stopped at any moment continues where it was.
"""

from __future__ import annotations

import json
import math
import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from qdsega.atomic import replaced_atomically
from qdsega.description import Formation, World, load_formation, named_world
from qdsega.description.formation_writer import formation_yaml
from qdsega.driver import error_line, run_jobs
from qdsega.errors import ConfigError, QdsegaError, QdsegaWarning, RunFolderError
from qdsega.progress import ProgressFactory
from qdsega.reform.candidates import AS_IT_IS, Candidate, Candidates
from qdsega.reform.folder import ReformFolder
from qdsega.reform.material import material_of
from qdsega.reform.outputs import write_outputs
from qdsega.reform.settings import ReformSettings
from qdsega.training.config import read_run_config, resolve_config
from qdsega.training.run import (
    TrainingInterrupted,
    completed_generations,
    train_or_resume,
    train_until,
)
from qdsega.training.run_folder import RunFolder

JOB_START_S = 5.0
"""What a candidate's run spends before its first generation (s): its process, the body in
PyBullet, its workers; added to the time its generations take for the estimate of time left."""
LATER_GENERATION_COST = 2.2
"""A generation after screening, against one of screening, in wall time (the median of the
reforms in docs/notes/2026-12-07-reform.md): for the learning's estimate of time left."""


@dataclass(frozen=True)
class CandidateJob:
    """A candidate's run as the driver's job: its first ``until`` generations (screening), or
    all of them and its evaluation (``until`` None); ``config`` sets settings over the
    candidate's own preset (a ``--config`` file)."""

    name: str
    formation: Path
    folder: Path
    world: Path | None
    seed: int
    workers: int
    until: int | None
    reference_trials: int
    config: Path | None = None

    def kept(self) -> bool:
        if self.until is None:
            return (self.folder / RunFolder.EVALUATION).is_file()
        folder = RunFolder(self.folder)
        return folder.finished or (
            folder.started and completed_generations(self.folder) >= self.until
        )

    def __call__(self) -> str | None:
        from qdsega.analysis.evaluation import evaluate_run  # starts PyBullet: in the job

        warnings.simplefilter("ignore", QdsegaWarning)  # a body that cannot move: its estimate
        try:
            formation = load_formation(self.formation)
            config = resolve_config(
                file=self.config,
                overrides={"sim": "memo", "seed": self.seed, "workers": self.workers},
                formation=formation,
            )
            world = None if self.world is None else named_world(self.world)
            if self.until is not None:
                train_until(
                    self.formation, config, self.folder, generations=self.until, world=world
                )
                return None
            train_or_resume(self.formation, config, self.folder, world=world)
            if RunFolder(self.folder).read_evaluation() is None:
                evaluate_run(self.folder, reference_trials=self.reference_trials)
        except TrainingInterrupted:
            raise
        except Exception as exc:  # a candidate that fails is dropped; the others go on
            return error_line(exc)
        return None


def reform(
    formation_file: Path,
    *,
    out: Path,
    world_file: Path | None = None,
    spares: dict[str, int] | None = None,
    repertoire: Path | None = None,
    config: Path | None = None,
    settings: ReformSettings | None = None,
    jobs: int = 1,
    ray: str | None = None,
    progress: ProgressFactory | None = None,
    log: Callable[[str], None] = print,
) -> dict[str, Any]:
    """Re-form the body of ``formation_file`` into ``out``; return the record (``reform.json``).

    Raises:
        FormationError: the body does not assemble, or cannot start in the world; a spare type
            no unit folder defines.
        WorldError: an unreadable world.
        RunFolderError: ``out`` holds another reform; ``repertoire`` is not a repertoire, or
            was built in another world; FormationError: the body cannot be adapted from it.
        ConfigError: bad settings, or no candidate moves at all.
    """
    start_time = time.perf_counter()
    settings = settings or ReformSettings()
    if jobs < 1:
        raise ConfigError(f"--jobs must be at least 1, got {jobs}")
    formation = load_formation(formation_file)
    world = World() if world_file is None else named_world(world_file)
    material = material_of(formation, spares or {})
    symmetric = (
        world.is_mirror_symmetric
        and abs(math.sin(world.lights(formation).light.bearing_rad)) < 1e-9
    )
    if repertoire is not None:
        _check_repertoire(repertoire, formation, world)
    if config is not None:
        resolve_config(file=config, overrides={"sim": "memo"}, formation=formation)
    inputs: dict[str, Any] = {
        "formation": formation.name,
        "formation_file": str(Path(formation_file).resolve()),
        "formation_yaml": Path(formation_file).read_text(encoding="utf-8"),
        "world": world.name,
        "world_file": None if world.file is None else str(world.file.resolve()),
        "spares": spares or {},
        "repertoire": None if repertoire is None else str(repertoire.resolve()),
        "config": None if config is None else config.read_text(encoding="utf-8"),
        "settings": asdict(settings),
    }
    candidates = Candidates(material, symmetric=symmetric)
    current = candidates.found[0]
    from qdsega.assembly import assemble  # trimesh and PyBullet: only once the input is read
    from qdsega.simulation.reach import check_reach

    check_reach(assemble(formation), allow_blocked=settings.allow_blocked)
    first = [current, *candidates.first_round()]
    allow_blocked = settings.allow_blocked
    problems = {c.name: _problem(c, formation, world, allow_blocked=allow_blocked) for c in first}
    if all(problems.values()):
        raise ConfigError(f"no candidate can move ({current.name}: {problems[current.name]})")
    folder = ReformFolder(out)
    _claim(folder, inputs)
    if config is not None:
        with replaced_atomically(folder.config) as partial:
            partial.write_text(inputs["config"], encoding="utf-8")
    state = Search(candidates, formation, world, folder, settings, jobs, ray, progress, log)
    state.screen(first, problems)
    for _ in range(settings.rounds - 1):
        state.screen(candidates.next_round(state.best(settings.widen)))
    if not any(e > 0 for e in state.estimates.values()):
        raise ConfigError("no candidate moved at all in screening (see reform.json)")
    learnt = state.learn([current, *state.best(settings.top, leave_out=current.name)])
    adapted = None if repertoire is None else _adapt(repertoire, formation, folder.adaptation)
    record = state.record(learnt, adapted, inputs, time.perf_counter() - start_time)
    write_outputs(record, candidates, folder, log=log)
    _write_record(folder, record)
    return record


class Search:
    """The candidates of one reform and what screening and learning found for them."""

    def __init__(
        self,
        candidates: Candidates,
        formation: Formation,
        world: World,
        folder: ReformFolder,
        settings: ReformSettings,
        jobs: int,
        ray: str | None,
        progress: ProgressFactory | None,
        log: Callable[[str], None],
    ) -> None:
        self.candidates = candidates
        self.formation = formation
        self.world = world
        self.folder = folder
        self.settings = settings
        self.jobs = jobs
        self.ray = ray
        self.progress = progress
        self.log = log
        self.dropped: dict[str, str] = {}
        self.estimates: dict[str, float] = {}
        self.screen_s: dict[str, float] = {}

    def job(self, candidate: Candidate, until: int | None) -> CandidateJob:
        return CandidateJob(
            name=candidate.name,
            formation=self.folder.candidate(candidate.name),
            folder=self.folder.run(candidate.name),
            world=self.world.file,
            seed=self.settings.seed,
            workers=1 if self.jobs > 1 else 2,
            until=until,
            reference_trials=self.settings.reference_trials,
            config=self.folder.config if self.folder.config.is_file() else None,
        )

    def screen(
        self, found: Sequence[Candidate], problems: dict[str, str | None] | None = None
    ) -> None:
        """Check ``found`` (unless ``problems`` says already what is wrong with each), write
        the formation file of each that passes and let it learn its first generations."""
        ready = []
        for candidate in found:
            if problems is not None:
                reason = problems[candidate.name]
            else:
                allowed = self.settings.allow_blocked
                reason = _problem(candidate, self.formation, self.world, allow_blocked=allowed)
            if reason is None:
                _write(candidate, self.formation, self.folder)
                ready.append(candidate)
            else:
                self.dropped[candidate.name] = reason
        self.log(
            f"qdsega reform: screening {len(ready)} candidates"
            f" ({len(found) - len(ready)} dropped), {self.settings.screen} generations each"
            + self._about(len(ready) * self._screen_s())
        )
        jobs = [self.job(c, self.settings.screen) for c in ready]
        errors = run_jobs(
            jobs, processes=self.jobs, ray=self.ray, label="screening", progress=self.progress
        )
        for candidate, job, error in zip(ready, jobs, errors, strict=True):
            if error is not None:
                self.dropped[candidate.name] = error
                continue
            metrics = RunFolder(job.folder).read_metrics()
            self.estimates[candidate.name] = float(metrics["greedy_exact_m"].max())
            self.screen_s[candidate.name] = float(metrics["wall_s"].sum())

    def _screen_s(self) -> float:
        """A candidate's screening so far, on average (s; 0 before any), and its start."""
        if not self.screen_s:
            return 0.0
        return sum(self.screen_s.values()) / len(self.screen_s) + JOB_START_S

    def _about(self, work_s: float) -> str:
        """``work_s`` of one process's work, spread over the jobs, in words ("" unknown)."""
        if work_s <= 0:
            return ""
        return f"; about {math.ceil(work_s / self.jobs / 60)} min"

    def best(self, count: int, *, leave_out: str | None = None) -> list[Candidate]:
        """The ``count`` screened candidates with the highest estimates (ties: fewer moves,
        then the first found)."""
        ranked = sorted(
            (c for c in self.candidates.found if c.name in self.estimates and c.name != leave_out),
            key=lambda c: (-self.estimates[c.name], len(c.moves), c.name),
        )
        return ranked[:count]

    def learn(self, chosen: Sequence[Candidate]) -> dict[str, dict[str, Any]]:
        """Learn ``chosen`` to the end and evaluate each; their evaluations by name. The time
        left is each one's own screening time, scaled to the generations left."""
        rest = [
            read_run_config(self.folder.run(c.name)).agent.genetic.generations
            - self.settings.screen
            for c in chosen
        ]
        self.log(
            f"qdsega reform: learning {len(chosen)} candidates to the end: "
            + ", ".join(c.name for c in chosen)
            + self._about(
                sum(
                    max(r, 0)
                    * LATER_GENERATION_COST
                    / self.settings.screen
                    * self.screen_s.get(c.name, 0.0)
                    + JOB_START_S
                    for c, r in zip(chosen, rest, strict=True)
                )
            )
        )
        jobs = [self.job(c, None) for c in chosen]
        errors = run_jobs(
            jobs, processes=self.jobs, ray=self.ray, label="learning", progress=self.progress
        )
        learnt = {}
        for candidate, job, error in zip(chosen, jobs, errors, strict=True):
            if error is not None:
                self.dropped[candidate.name] = error
                continue
            folder = RunFolder(job.folder)
            evaluation = folder.read_evaluation()
            assert evaluation is not None, "a learnt candidate is evaluated"
            learnt[candidate.name] = {
                "distance_m": evaluation["distance_m"],
                "failure": evaluation["failure"],
                "run": str(job.folder),
                "preset": folder.read_summary()["preset"],
                "wall_s": folder.read_summary()["wall_s"],
            }
        return learnt

    def record(
        self,
        learnt: dict[str, dict[str, Any]],
        adapted: dict[str, Any] | None,
        inputs: dict[str, Any],
        wall_s: float,
    ) -> dict[str, Any]:
        """Everything the reform found: each candidate, the winner, its plan."""
        rows = []
        for candidate in self.candidates.found:
            rows.append(
                {
                    "name": candidate.name,
                    "how": candidate.how,
                    "moves": [_move(m) for m in candidate.moves],
                    "units": len(candidate.arrangement.attached),
                    "joints": len(candidate.arrangement.formation("", "").joints),
                    "estimate_m": self.estimates.get(candidate.name),
                    "screen_s": self.screen_s.get(candidate.name),
                    "distance_m": learnt.get(candidate.name, {}).get("distance_m"),
                    "learn_s": learnt.get(candidate.name, {}).get("wall_s"),
                    "preset": learnt.get(candidate.name, {}).get("preset"),
                    "dropped": self.dropped.get(candidate.name),
                }
            )
        current = self.candidates.found[0].name
        best = max(learnt, key=lambda n: learnt[n]["distance_m"], default=current)
        relearnt_m = learnt.get(current, {}).get("distance_m")
        adapted_m = None if adapted is None else adapted["distance_m"]
        baseline = max((d for d in (relearnt_m, adapted_m) if d is not None), default=0.0)
        reformed = best != current and learnt[best]["distance_m"] > baseline
        winner = best if reformed else current
        how = "re-formed" if reformed else _as_it_is(relearnt_m, adapted_m)
        adapted_wins = how == "as it is, adapted"
        return {
            "inputs": inputs,
            "candidates": rows,
            "current": {"name": current, "relearnt_m": relearnt_m, "adapted": adapted},
            "winner": {
                "name": winner,
                "reformed": reformed,
                "how": how,
                "distance_m": learnt[best]["distance_m"] if reformed else baseline,
                "run": None if adapted_wins else learnt.get(winner, {}).get("run"),
                "adaptation": adapted["folder"] if adapted_wins and adapted is not None else None,
                "moves": [_move(m) for m in self.candidates.by_name(winner).moves],
            },
            "wall_s": wall_s,
        }


def _as_it_is(relearnt_m: float | None, adapted_m: float | None) -> str:
    if adapted_m is not None and (relearnt_m is None or adapted_m > relearnt_m):
        return "as it is, adapted"
    return "as it is, relearnt"


def _move(move: Any) -> dict[str, Any]:
    return {
        "unit": move.unit,
        "leaves": None if move.leaves is None else str(move.leaves),
        "takes": None if move.takes is None else str(move.takes),
    }


def _body(candidate: Candidate, original: Formation) -> Formation:
    """The candidate as a formation, named after the original (the original's own name for the
    body as it is)."""
    name = original.name if candidate.how == AS_IT_IS else f"{original.name}_{candidate.name}"
    return candidate.arrangement.formation(name, f"{original.name} re-formed: {candidate.how}")


def _problem(
    candidate: Candidate, original: Formation, world: World, *, allow_blocked: bool
) -> str | None:
    """Why the candidate cannot move, checked as ``assemble`` and ``train`` would check it
    (levels a joint cannot reach only without ``allow_blocked``: the user was warned of the
    body as it is); None where nothing is wrong."""
    from qdsega.assembly import assemble  # trimesh and PyBullet: only where bodies are checked
    from qdsega.simulation.reach import check_reach
    from qdsega.training.sims import check_sim

    body = _body(candidate, original)
    if not body.joints:
        return "no working joint"
    try:
        if not allow_blocked:
            check_reach(assemble(body))
        config = resolve_config(overrides={"sim": "memo"}, formation=body)
        check_sim(world.lights(body), config, world)
    except QdsegaError as exc:
        return exc.message
    return None


def _write(candidate: Candidate, original: Formation, folder: ReformFolder) -> None:
    """The candidate's formation file, headed by how it was made."""
    body = _body(candidate, original)
    file = folder.candidate(candidate.name)
    file.parent.mkdir(parents=True, exist_ok=True)
    moves = "; ".join(str(m) for m in candidate.moves) or "none"
    text = formation_yaml(body, file, comment=f"{body.name}: {candidate.how}\nmoves: {moves}")
    with replaced_atomically(file) as partial:
        partial.write_text(text, encoding="utf-8")


def _check_repertoire(repertoire: Path, formation: Formation, world: World) -> None:
    """Refuse a repertoire the body cannot be adapted from, before anything is written.

    Raises:
        RunFolderError: not a repertoire, or one built in another world.
        FormationError: no joint in common with the body, or no gait that walks.
    """
    from qdsega.adaptation.adapt import MappedRepertoire
    from qdsega.training.formation_copy import load_run_world

    MappedRepertoire.of(repertoire, formation)
    built_in = load_run_world(repertoire)
    if built_in.name != world.name:
        message = f"built in {built_in.name}, and this reform is in {world.name}"
        raise RunFolderError(message, file=repertoire)


def _adapt(repertoire: Path, formation: Formation, folder: Path) -> dict[str, Any]:
    """The body as it is, adapted from the repertoire into ``folder`` (kept once done)."""
    from qdsega.adaptation.adapt import adapt, is_adaptation
    from qdsega.adaptation.folders import AdaptationFolder

    if is_adaptation(folder):
        result = json.loads(AdaptationFolder(folder).result.read_text(encoding="utf-8"))
    else:
        result = adapt(repertoire, formation, folder)
    return {
        "distance_m": result["distance_m"],
        "trials": len(result["trials"]),
        "wall_s": result["wall_s"],
        "folder": str(folder),
    }


def _claim(folder: ReformFolder, inputs: dict[str, Any]) -> None:
    """Make ``folder`` this reform's: new, one that holds only the body's own file (``qdsega
    design`` writes its first body there), or one that holds this same reform.

    Raises:
        RunFolderError: the folder holds something else, or another reform.
    """
    out, record = folder.path, folder.record
    own = Path(inputs["formation_file"])
    if record.is_file():
        previous = json.loads(record.read_text(encoding="utf-8"))
        earlier = previous.get("inputs", {})
        if "settings" in earlier:  # a reform begun before a setting existed had its default
            earlier["settings"] = {**asdict(ReformSettings()), **earlier["settings"]}
        if earlier != inputs:
            message = (
                "holds another reform (other body, world, spares or settings); choose another --out"
            )
            raise RunFolderError(message, file=out)
        return
    if out.exists() and (not out.is_dir() or any(p.resolve() != own for p in out.iterdir())):
        raise RunFolderError("not empty and not a reform's folder; choose another --out", file=out)
    _write_record(folder, {"inputs": inputs})


def _write_record(folder: ReformFolder, record: dict[str, Any]) -> None:
    folder.path.mkdir(parents=True, exist_ok=True)
    with replaced_atomically(folder.record) as partial:
        partial.write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
