"""Calibration: the scene's parameters that make a run's observable meet measurements, by
scipy.optimize.least_squares, the Jacobian's runs spread like a sweep's."""

import dataclasses

import numpy as np

from .scene_paths import get_path, scene_dict
from .sweep import run_many, scenes_of

OBSERVABLES = ("max_forces", "post_impact_velocities", "impulses")


@dataclasses.dataclass
class FitResult:
    """values and standard_errors: dicts keyed by the dotted paths; residuals: (model - data) /
    sigma at the solution; runs: the run_chain() calls made; covariance: of the values, in the
    order of `parameters`; result: the last run; optimizer: scipy's OptimizeResult."""

    values: dict
    standard_errors: dict
    residuals: np.ndarray
    runs: int
    covariance: np.ndarray
    result: object
    optimizer: object


def _observable(observable, contacts, bodies):
    """The function of a result that the data measure."""
    if callable(observable):
        if contacts is not None or bodies is not None:
            raise ValueError("contacts and bodies select entries of a named observable; "
                             "allowed with a callable: neither")
        return lambda result: np.atleast_1d(np.asarray(observable(result), dtype=float))
    if observable not in OBSERVABLES:
        raise ValueError(f"observable = {observable!r} is not allowed; allowed: "
                         f"{', '.join(OBSERVABLES)} or a callable on the result")
    per_body = observable == "post_impact_velocities"
    chosen, wrong, name = (bodies, contacts, "bodies") if per_body else (contacts, bodies,
                                                                          "contacts")
    if wrong is not None:
        raise ValueError(f"{'contacts' if per_body else 'bodies'} given for {observable}, which "
                         f"is per {'body' if per_body else 'contact'}; allowed: {name}")
    index = None if chosen is None else _indices(chosen, name)

    def measure(result):
        values = getattr(result, observable)
        if index is not None and (index.min() < 0 or index.max() >= values.size):
            raise ValueError(f"{name} = {chosen} is not allowed; allowed: indices 0 <= i < "
                             f"{values.size}")
        return values if index is None else values[index]
    return measure


def _indices(chosen, name):
    """Whole, finite indices as an int array; fractions are refused, never truncated."""
    try:
        values = np.asarray(chosen)
    except (TypeError, ValueError):
        values = np.asarray([None])
    whole = values.ndim == 1 and values.size > 0 and (
        values.dtype.kind in "iu" or (values.dtype.kind == "f" and np.all(np.isfinite(values))
                                      and np.all(values == np.floor(values))))
    if not whole:
        raise ValueError(f"{name} = {chosen!r} is not allowed; allowed: a non-empty list of "
                         "whole indices")
    return values.astype(int)


def _bounds(scene, parameters):
    """Lower and upper bounds, each checked to be a valid value of its field."""
    if not isinstance(parameters, dict) or not parameters:
        raise ValueError(f"parameters = {parameters!r} is not allowed; allowed: a non-empty dict "
                         "from dotted paths to (lower, upper) bounds")
    lower, upper = [], []
    for path, bound in parameters.items():
        try:
            low, high = (float(b) for b in bound)
        except (TypeError, ValueError):
            raise ValueError(f"parameters[{path!r}] = {bound!r} is not allowed; allowed: "
                             "(lower, upper)") from None
        if not (np.isfinite(low) and np.isfinite(high) and low < high):
            raise ValueError(f"parameters[{path!r}] = ({low}, {high}) is not allowed; allowed: "
                             "finite lower < upper")
        lower.append(low)
        upper.append(high)
    for point in ({p: l for p, l in zip(parameters, lower)},
                  {p: u for p, u in zip(parameters, upper)}):
        try:
            scenes_of(scene, [point])
        except ValueError as error:
            raise ValueError(f"bounds outside the field's allowed range: {error}") from None
    return np.array(lower), np.array(upper)


def _start(scene, parameters, lower, upper, start):
    """The first guess: `start` (refused outside the bounds), else the scene's value when inside
    the bounds, else the middle."""
    if start is not None:
        if not isinstance(start, dict):
            raise ValueError(f"start = {start!r} is not allowed; allowed: a dict from parameters "
                             "to first values")
        for path in start:
            if path not in parameters:
                raise ValueError(f"start[{path!r}] is not allowed; allowed: the parameters "
                                 f"{', '.join(map(repr, parameters))}")
    guess = []
    for k, path in enumerate(parameters):
        if start is not None and path in start:
            try:
                value = float(start[path])
            except (TypeError, ValueError):
                value = float("nan")
            if not lower[k] <= value <= upper[k]:
                raise ValueError(f"start[{path!r}] = {start[path]!r} is not allowed; allowed: "
                                 f"within its bounds [{lower[k]}, {upper[k]}]")
        else:
            try:
                value = float(get_path(scene, path))
            except (ValueError, TypeError, KeyError):
                value = 0.5 * (lower[k] + upper[k])
            if not lower[k] <= value <= upper[k]:
                value = 0.5 * (lower[k] + upper[k])
        guess.append(value)
    return np.array(guess)


def fit(scene, parameters, observable, data, sigma=None, contacts=None, bodies=None,
        client=None, start=None, relative_step=1e-4, **options):
    """The values of the scene's `parameters` ({dotted path: (lower, upper)}) for which the
    runs' `observable` best meets `data` in the least-squares sense.

    observable: "max_forces", "post_impact_velocities" or "impulses", restricted to the listed
    `contacts` or `bodies` when given, or a callable on the run_chain() result returning an
    array. sigma: the data's standard deviations (a number or one per datum); the standard
    errors then follow from them, else from the residuals' scatter. The Jacobian is by forward
    differences of `relative_step` of each parameter's range, its runs spread on the local
    cores or on the Dask `client`, like a sweep's. `options` go to scipy.optimize.least_squares.
    """
    from scipy.optimize import least_squares

    base = scene_dict(scene)
    paths = list(parameters) if isinstance(parameters, dict) else []
    lower, upper = _bounds(base, parameters)
    measure = _observable(observable, contacts, bodies)
    data = np.atleast_1d(np.asarray(data, dtype=float))
    weights = np.ones_like(data) if sigma is None else np.broadcast_to(
        np.asarray(sigma, dtype=float), data.shape).copy()
    if np.any(~np.isfinite(data)):
        raise ValueError("data holds values that are not finite; allowed: finite numbers")
    if not np.all(np.isfinite(weights) & (weights > 0)):
        raise ValueError(f"sigma = {sigma!r} is not allowed; allowed: finite numbers > 0, one or "
                         f"one per datum ({data.size})")
    if not (isinstance(relative_step, (int, float)) and 0 < relative_step < 1):
        raise ValueError(f"relative_step = {relative_step!r} is not allowed; allowed: a share "
                         "0 < relative_step < 1 of each parameter's range")
    first = _start(base, parameters, lower, upper, start)
    runs = 0
    cache = {}

    def residuals_at(points):
        """Weighted residuals of each point, running those not seen yet."""
        nonlocal runs
        missing = [p for p in points if p.tobytes() not in cache]
        if missing:
            scenes = scenes_of(base, [dict(zip(paths, p.tolist())) for p in missing])
            for p, result in zip(missing, run_many(scenes, client=client)):
                model = measure(result)
                if model.shape != data.shape:
                    raise ValueError(f"data has {data.size} values; allowed: {model.size}, the "
                                     "observable's")
                cache[p.tobytes()] = ((model - data) / weights, result)
            runs += len(missing)
        return [cache[p.tobytes()][0] for p in points]

    steps = relative_step * (upper - lower)

    def jacobian(x):
        shifted = []
        for k in range(x.size):  # forward, or backward at the upper bound
            point = x.copy()
            point[k] += steps[k] if x[k] + steps[k] <= upper[k] else -steps[k]
            shifted.append(point)
        at_x, *around = residuals_at([x] + shifted)
        return np.column_stack([(r - at_x) / (p[k] - x[k])
                                for k, (r, p) in enumerate(zip(around, shifted))])

    solution = least_squares(lambda x: residuals_at([x])[0], first, jac=jacobian,
                             bounds=(lower, upper), x_scale=upper - lower, **options)
    J = jacobian(solution.x)
    covariance = np.linalg.pinv(J.T @ J)
    if sigma is None:  # the scatter of the residuals stands for the unknown sigma
        dof = max(data.size - solution.x.size, 1)
        covariance *= float(solution.fun @ solution.fun) / dof
    errors = np.sqrt(np.diag(covariance))
    return FitResult(values=dict(zip(paths, solution.x.tolist())),
                     standard_errors=dict(zip(paths, errors.tolist())),
                     residuals=solution.fun, runs=runs, covariance=covariance,
                     result=cache[solution.x.tobytes()][1], optimizer=solution)
