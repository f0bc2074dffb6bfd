"""Pareto dominance, the one definition the Python tools share: the report's Pareto panels
(glintlab_report.py) and tune's fronts (experiments/tune/glintlab_tune.py).

Every objective is minimised. slack[k] is how far apart two values of objective k may be and still
not be ranked apart (a truth's noise floor, summary.json references[].floor); 0 where not given."""


def dominates(a, b, slack=None):
    """True when a dominates b: no worse than b on every objective (beyond the slack), and better
    on at least one beyond it."""
    s = slack if slack is not None else [0.0] * len(a)
    return (all(x <= y + e for x, y, e in zip(a, b, s))
            and any(x < y - e for x, y, e in zip(a, b, s)))


def front(items, values, slack=None):
    """The items no other item dominates, in their given order. values(item): its objectives;
    slack(p, q): the slack vector for comparing items p and q (None: none)."""
    return [p for p in items
            if not any(dominates(values(q), values(p), slack(q, p) if slack else None)
                       for q in items if q is not p)]
