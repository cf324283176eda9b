"""An ensemble's members and results, shared by Model, Lagrangian and the command-line wrappers:
the members' arrays from keyword arguments, the result dict (or Interrupted with it), and the
message for an unknown keyword."""

import difflib

import numpy as np

from .errors import Interrupted, UsageError


def _keyword_error(function, key, valid):
    near = difflib.get_close_matches(key, valid, n=3, cutoff=0.6)
    hint = f"; did you mean {' or '.join(repr(n) for n in near)}?" if near else ""
    return TypeError(f"{function}() got an unexpected keyword argument {key!r}{hint} "
                     f"(valid: {', '.join(sorted(valid))})")



def _member_arrays(function, parameters, defaults, names, q0, p0, d):
    """An ensemble's arrays, one row per member: the parameters' values (``parameters`` maps
    names to one value per member, the others at ``defaults``), q0 and p0 (members × d; empty
    where not given: each member's default start; p0 zero where q0 alone is given)."""
    parameters = dict(parameters or {})
    for key in parameters:
        if key not in names:
            raise _keyword_error(function, key, names)
    sizes = {len(np.atleast_1d(v)) for v in parameters.values()}
    if q0 is not None:
        q0 = np.atleast_2d(np.asarray(q0, dtype=float))
        p0 = np.zeros_like(q0) if p0 is None else np.atleast_2d(np.asarray(p0, dtype=float))
        sizes.add(len(q0))
    if len(sizes) > 1:
        raise UsageError(f"the members' arrays have different lengths: {sorted(sizes)}")
    n = sizes.pop() if sizes else 1
    values = np.empty((n, len(names)))
    for k, name in enumerate(names):
        values[:, k] = np.broadcast_to(parameters.get(name, defaults[name]), n)
    empty = np.empty((0, d))
    return values, (empty if q0 is None else q0), (empty if q0 is None else p0)


def _ensemble_result(out):
    """An ensemble's dict, or Interrupted (Ctrl-C) with it in ``partial``: the members done,
    those stopped in flight ("stopped", at the state reached) and those not run ("not run")."""
    if out.pop("interrupted"):
        done = sum(s not in ("stopped", "not run") for s in out["status"])
        raise Interrupted(f"ensemble interrupted with {done} of {len(out['status'])} members done; "
                          "all are in .partial (status 'stopped' or 'not run' for the others)",
                          partial=out)
    return out
