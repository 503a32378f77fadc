# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The order of a system's instances (the model's ``after``), and what became of them."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, List, Mapping, Sequence, Set

#: instance name -> the instances that must be active first
After = Mapping[str, Sequence[str]]


def order(after: After) -> List[str]:
    """Return the instances in an order where each comes after those it names."""
    ordered: List[str] = []
    todo = dict(after)
    while todo:
        ready = sorted(n for n, first in todo.items()
                       if all(a in ordered or a not in after for a in first))
        if not ready:
            # a cycle (the model's check refuses them): keep the rest as named
            ready = sorted(todo)
        ordered += ready
        for name in ready:
            del todo[name]
    return ordered


def predecessors(after: After, name: str) -> Set[str]:
    """Return the instances that name comes after, directly or not."""
    seen: Set[str] = set()
    todo = list(after[name])
    while todo:
        other = todo.pop()
        if other not in seen:
            seen.add(other)
            todo += after.get(other, [])
    return seen


def successors(after: After, name: str) -> List[str]:
    """Return the instances that come after name, directly or not."""
    waiting: Set[str] = set()
    grew = True
    while grew:
        grew = False
        for candidate, first in after.items():
            if candidate not in waiting and (name in first or waiting & set(first)):
                waiting.add(candidate)
                grew = True
    return sorted(waiting)


@dataclass
class Outcome:
    """What became of the instances: active, failed (and why), held back (by what)."""

    active: List[str] = field(default_factory=list)
    failed: Dict[str, str] = field(default_factory=dict)
    held_back: Dict[str, List[str]] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        """Tell whether every instance is active."""
        return not self.failed and not self.held_back


def report(outcome: Outcome, total: int) -> str:
    """Return the final report of a bring-up, one line per problem."""
    lines = [f'bringup: {len(outcome.active)} of {total} managed instances active']
    lines += [f'bringup: {name} failed: {why}' for name, why in sorted(outcome.failed.items())]
    lines += [f"bringup: {name} held back by {', '.join(by)}"
              for name, by in sorted(outcome.held_back.items())]
    return '\n'.join(lines)
