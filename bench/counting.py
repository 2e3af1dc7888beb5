"""What the benchmark scripts share: a function under a budget of calls
(every call counted, as a solver's user would count them), and the lists of
integers their command lines take."""

import numpy as np


class BudgetExhausted(Exception):
    """Raised at the attempt of call budget + 1."""


class Counted:
    """``fun(x) -> float`` under a budget of calls: ``evaluate`` counts each
    call in ``calls`` and raises BudgetExhausted at the attempt of call
    budget + 1. Each script's wrapper adds what it keeps of the values."""

    def __init__(self, fun, budget):
        self.fun = fun
        self.budget = int(budget)
        self.calls = 0

    def evaluate(self, x):
        """``fun(x)`` as a float, ``x`` flattened to a float vector."""
        if self.calls >= self.budget:
            raise BudgetExhausted
        self.calls += 1
        return float(self.fun(np.asarray(x, dtype=float).ravel()))


def int_list(text):
    """``"1-3,7"`` -> ``[1, 2, 3, 7]``: comma-separated integers and ranges
    ``a-b``, both ends included (a leading ``-`` is a sign)."""
    out = []
    for part in text.split(","):
        part = part.strip()
        if "-" in part[1:]:
            a, b = part.split("-", 1)
            out.extend(range(int(a), int(b) + 1))
        elif part:
            out.append(int(part))
    return out
