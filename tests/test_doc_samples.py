"""The sample outputs in the README and the guides have the form the commands print today:
each sample line is compared with what train and evaluate printed for a tiny run, with the
numbers, names and paths (which differ between the two runs) masked."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = (  # page, a phrase that marks the sample line
    ("README.md", "generation 30/30: exact"),
    ("README.md", "greedy policy of generation"),
    ("README.md", ": learnt policy "),
    ("docs/commands.md", ": learnt policy "),
)
_MASKS = (
    (re.compile(r", [\d.]+% of commands failed \([^)]*\)"), ""),  # only where commands failed
    (re.compile(r"^\S+: "), "BODY: "),
    (re.compile(r"-> \S+$"), "-> PATH"),
    (re.compile(r"best reference: [^\d]+ "), "best reference: NAME "),
    (re.compile(r"generation \d+/\d+"), "generation #/#"),
    (re.compile(r"\d[\d,]*(\.\d+)?"), "#"),
)


def _shape(line: str) -> str:
    for pattern, mask in _MASKS:
        line = pattern.sub(mask, line.strip())
    return line


def _sample(page: str, phrase: str) -> str:
    lines = [line for line in (ROOT / page).read_text().splitlines() if phrase in line]
    assert lines, f"{page} holds no sample line with {phrase!r}"
    return lines[0]


@pytest.mark.parametrize(("page", "phrase"), SAMPLES)
def test_a_sample_line_has_the_form_the_command_prints(page, phrase, tiny_run):
    printed = (tiny_run.parent / "printed.txt").read_text().replace("\r", "\n").splitlines()
    shapes = {_shape(line) for line in printed if line.strip()}
    assert _shape(_sample(page, phrase)) in shapes, f"{page}: {_sample(page, phrase)}"


def test_the_mask_keeps_what_tells_two_forms_apart():
    printed = "snake5: learnt policy 0.0692 m (memo predicted 0.0497 m); ratio 0.172 -> r/e.json"
    assert _shape(printed) == "BODY: learnt policy # m (memo predicted # m); ratio # -> PATH"
    assert _shape(printed.replace("memo predicted", "table predicted")) != _shape(printed)
