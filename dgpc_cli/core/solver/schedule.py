"""Weight schedules: a constant weight, or one that moves linearly from A to B (``0.01->0``)."""

from __future__ import annotations

from dataclasses import dataclass

#: Iterations over which a schedule ``A->B`` moves from A to B (paper §5.2 lowers such weights
#: "during the editing process"; we lower them over the first iterations of each step).
SCHEDULE_ITERATIONS = 20


@dataclass(frozen=True)
class Schedule:
    """A weight as a function of the iteration: ``start`` at 0, ``end`` from ``iterations`` on."""

    start: float
    end: float
    iterations: int = SCHEDULE_ITERATIONS

    @classmethod
    def constant(cls, value: float) -> Schedule:
        return cls(float(value), float(value), 0)

    def __call__(self, k: int) -> float:
        if self.iterations <= 0 or k >= self.iterations:
            return self.end
        t = k / self.iterations
        return self.start + (self.end - self.start) * t

    def settled(self, k: int) -> bool:
        """True once the weight has reached its final value."""
        return self.iterations <= 0 or k >= self.iterations or self.start == self.end

    def __str__(self) -> str:
        return f"{self.start:g}" if self.start == self.end else f"{self.start:g}->{self.end:g}"


def parse_weight(text: str) -> tuple[str, Schedule]:
    """Parse ``NAME=VALUE`` or ``NAME=A->B``; raises ValueError with a one-line reason."""
    name, sep, value = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise ValueError(f"weight {text!r} is not of the form NAME=VALUE or NAME=A->B")
    parts = value.split("->")
    if len(parts) > 2:
        raise ValueError(f"weight {text!r} has more than one '->'")
    try:
        numbers = [float(p) for p in parts]
    except ValueError:
        raise ValueError(f"weight {text!r}: {value!r} is not a number or A->B") from None
    if any(not (v >= 0.0) or v == float("inf") for v in numbers):
        raise ValueError(f"weight {text!r}: weights must be finite and ≥ 0")
    if len(numbers) == 1:
        return name, Schedule.constant(numbers[0])
    return name, Schedule(numbers[0], numbers[1])
