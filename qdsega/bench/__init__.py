"""Benchmarks: QDSEGA against the learners a user would pick instead, same task, same budget.

``qdsega bench`` (:mod:`qdsega.bench.runner`) runs every method of :mod:`qdsega.bench.methods`
on every task of :mod:`qdsega.bench.tasks` for several seeds, keeps each result as it finishes
(a re-run skips what finished), and writes ``BENCHMARKS.md`` with its figures
(:mod:`qdsega.bench.report`).
"""
