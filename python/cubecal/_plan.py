"""cubecal.plan: how long to record, as `cubecal plan`; the result's
to_dict() is the whole plan (its rows are `plan --format json`)."""
import json
import os

from . import _args, _cubecal
from ._analyze import Analysis
from ._data import string_list
from ._model import NoiseModel
from ._result import Result, _fmt


class PlanTargetSpec(Result):
    """One target planned: a term and the precision asked of it."""

    __slots__ = ()
    _spec = """
    term: str -- the term: "Q", "N", "B", "K", "R" or "T"
    precision: float -- the relative half-width asked of its interval at the plan's ci (0.10: +-10 %)
    """


class PlanChannel(Result):
    """One channel planned."""

    __slots__ = ()
    _spec = """
    name: str -- the channel's name (the axis, or "datasheet")
    unit: str -- its data unit
    """


class PlanRow(Result):
    """One row of a plan: a channel's term, with the record length its
    target needs (kind "target") or its precision at the asked length (kind
    "duration")."""

    __slots__ = ()
    _spec = """
    channel: str -- the channel
    term: str -- the term: "Q", "N", "B", "K", "R" or "T"
    kind: str -- "target" (the length a target needs) or "duration" (the precision at the asked length)
    precision: float | None -- the target, or the precision at the asked length (relative half-width at ci;
        None where the term is not resolved)
    duration_s: float | None -- the shortest record that meets the target, s (None when none does), or the
        asked length
    achieved: float | None -- the precision at duration_s (at most the target)
    value: float | None -- the term's value in the unit quoted for the sensor (None when not resolved)
    unit: str -- that unit (deg/sqrt(h), deg/h, ...; T in s)
    tau_lo: float | None -- the lowest tau the term is read from, s
    tau_hi: float | None -- the highest, s
    reason: str | None -- None when planned; else "not in model", "not resolved", "rate too low",
        "finer than model" or "too long"
    why: str | None -- the reason in a sentence (None when planned)
    """

    def _summary(self):
        if self.reason is not None:
            return f"{self.channel} {self.term}: {self.reason}"
        if self.kind == "target":
            return f"{self.channel} {self.term}: {_fmt(100 * self.precision)} % in {_fmt(self.duration_s)} s"
        return f"{self.channel} {self.term}: {_fmt(100 * self.precision)} % at {_fmt(self.duration_s)} s"


class PlanCurve(Result):
    """A term's precision against record length, for a plot."""

    __slots__ = ()
    _spec = """
    channel: str -- the channel
    term: str -- the term
    duration_s: array -- record lengths, s, ascending (log-spaced)
    precision: array -- the precision at each (relative half-width at ci; NaN where not resolved)
    """


class Plan(Result):
    """The result of cubecal.plan: the record length each target needs and
    the precision at a length, per channel and term, with each term's
    precision curve."""

    __slots__ = ()
    _spec = """
    command: str -- "plan"
    source: str -- where the models come from: "preset", "twin", "random-walk", "model" or "datasheet"
    source_name: str -- the presets' names, the file's path or the datasheet's text
    source_note: str -- what the source gave, in words
    rate_hz: float -- the sampling rate planned at, Hz
    ci: float -- the confidence of every precision (0 to 1)
    defaults: bool -- True when neither target nor duration was given: the defaults were planned
    duration_s: float | None -- the record length whose precision was planned, s
    targets: list[PlanTargetSpec] -- the targets planned
    channels: list[PlanChannel] -- the channels planned
    rows: list[PlanRow] -- one per channel and term (as `cubecal plan --format json`)
    curves: list[PlanCurve] -- one per channel and term
    """

    def _summary(self):
        return f"{self.source} {self.source_name} at {_fmt(self.rate_hz)} Hz; " + "; ".join(
            r._summary() for r in self.rows)


def _target_text(target):
    if isinstance(target, str):
        return target
    if isinstance(target, dict):
        items = []
        for term, precision in target.items():
            if not isinstance(term, str):
                raise _args.usage("target", f"target: a term's letter is expected as a key, not {term!r}")
            items.append(f"{term}:{_args.number(precision, 'target')!r}")
        return ",".join(items)
    raise _args.usage("target", f"target: \"B:10%,N:1%\" or {{\"B\": 0.1, \"N\": 0.01}} is expected, not {target!r}")


def _set_model(a, model):
    if isinstance(model, Analysis):
        a.analysis = model._handle
    elif isinstance(model, NoiseModel):
        a.model_json = json.dumps(model.to_dict())
    elif isinstance(model, os.PathLike) or (isinstance(model, str) and model.endswith(".json")):
        a.model_file = os.fspath(model)
    elif isinstance(model, (str, list, tuple)):
        a.presets = string_list(model, "model")
    else:
        raise _args.usage("model", "model: a preset name, an Analysis, a NoiseModel or the path of an "
                                   f"analysis.json, not {type(model).__name__}")


@_args.public
def plan(model=None, target=None, duration=None, datasheet=None, rate=None, ci=0.683, taus="log:10"):
    """How long to record: the record length each noise term needs for a
    target precision, or the precision a record of a given length gives, as
    `cubecal plan`.

    The plan is the analysis of the record the model would give, made on the
    model's own Allan curve (EDF of the statistic at the taus each term is
    read from; for B and T the spread of the curve's minimum):
    docs/formulas/planning.md. With neither `target` nor `duration`, both
    for the defaults: the length for B:10%,N:1%,K:20%,T:30% and the
    precision at the paper's 72 h.

    Parameters
    ----------
    model : str, list of str, Analysis, NoiseModel or os.PathLike, optional
        A preset name or a list of them (`cubecal.presets()`), an Analysis of
        `cubecal.analyze` (its twins, else its random-walk model), a
        NoiseModel of `cubecal.model`, or the path of an analysis.json or of
        the JSON of `cubecal model --format json`.
    target : str or dict, optional
        Targets, "B:10%,N:1%,K:20%,T:30%" or {"B": 0.1, "N": 0.01}: each the
        half-width of the term's interval at `ci` relative to the term
        (0 < precision < 1); terms Q, N, B, K, R, T.
    duration : float or str, optional
        A record length whose precision to plan, s, or a duration text
        ("72h", "30m", "2d").
    datasheet : str, optional
        Datasheet terms instead of a model, e.g.
        "N=0.15deg/rth,B=6deg/h,K=0.02deg/h/rth" (Q, N, B, K, R with their
        units); needs `rate`.
    rate : float, optional
        Sampling rate of the record to plan, Hz. Default: the model's (a
        preset's 10 Hz); a model is rescaled to it, keeping its N and K.
    ci : float
        Confidence of the precisions (0 to 1; 0.683: 1 sigma).
    taus : str or array_like
        The tau grid of the analysis planned ("log:10", "octave", ...) or
        taus in seconds.

    Returns
    -------
    Plan
        Per channel and term a row (rows: its value, the target, the length
        it needs or the precision at the length, or why neither), and each
        term's precision against record length (curves).

    Raises
    ------
    cubecal.UsageError
        A bad argument (.option names it): no model or two, an unknown term,
        a precision of 0 or of 100 % or more, a datasheet without rate or
        with a unit that is not one of its term.
    """
    a = _cubecal._PlanArgs()
    if model is not None:
        _set_model(a, model)
    if datasheet is not None:
        a.datasheet = _args.text(datasheet, "datasheet")
        if not a.datasheet.strip():
            raise _args.usage("datasheet", "datasheet: the terms are empty (e.g. \"N=0.15deg/rth,B=6deg/h\")")
    if rate is not None:
        a.rate = _args.rate(rate)
    if target is not None:
        a.target = _target_text(target)
        if not a.target:
            raise _args.usage("target", "target: no target given")
    if isinstance(duration, str):
        try:
            a.duration = _cubecal._parse_duration(duration)
        except _cubecal.UsageError as e:
            raise _args.usage("duration", str(e)) from None
    elif duration is not None:
        a.duration = _args.number(duration, "duration", positive=True)
    a.ci = _args.number(ci, "ci")
    grid = _args.taus(taus, "taus")
    if grid is None:
        grid = "log:10"
    a.taus = grid if isinstance(grid, str) else ",".join(repr(float(t)) for t in grid)
    return Plan(_cubecal._plan(a))
