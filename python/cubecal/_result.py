"""Typed results: the JSON documents of the commands as classes with fields.

Every result of the library has a JSON form (what the CLI writes:
analysis.json, `model --format json`, the calibration files). The binding
turns the library's document value into Python objects in one pass, every
array of numbers a read-only NumPy array made in C++ (python/src/json_value.cpp:
no JSON text on the way); a Result subclass declares the fields of one kind
of object (name, type, meaning with its unit) and wraps its nested objects
in their own classes on their first access (making a result costs one
object, however large its document), so that `a.channels[0].noise.reported.white_noise.value`
is a float, `a.channels[0].adev.dev` a float64 array, `a["channels"]` the
same list as `a.channels`, and `a.to_dict()` the command's JSON content
(json.loads of its text: arrays as lists, NaN as None).

A class's fields are declared in its `_spec`, one per line:

    name: type -- meaning, with its unit
    name?: type -- a field the document holds only sometimes (None when absent)

with type one of float, int, str, bool, Any, array (float64), int_array,
bool_array, matrix (2-D float64), ndarray (any dtype or shape), list[str],
a Result class's name, or list[ClassName]; `| None` where the value may be null. The class's numpydoc
docstring gets an Attributes section from it, and its type stub
(cubecal/*.pyi) is generated from it by scripts/result-stubs.py (the test
test_typed_results.Stubs checks that they agree).
"""
import json
import re

import numpy as np

__all__ = ["Result"]

_REGISTRY = {}
_LINE = re.compile(r"^\s*(\w+)(\??)\s*:\s*([^-]+?)\s*--\s*(.*)$")
_ARRAY_TYPES = {"array": np.float64, "int_array": np.int64, "bool_array": np.bool_, "matrix": np.float64}


def _parse_spec(spec):
    """{name: (type text, optional, meaning)} of a _spec; a meaning may go on
    over the next lines (indented further than the field's line)."""
    fields = {}
    last = None
    for line in spec.strip("\n").splitlines():
        if not line.strip():
            continue
        m = _LINE.match(line)
        if m and not line.startswith("        "):
            last = m.group(1)
            fields[last] = [m.group(3).strip(), bool(m.group(2)), m.group(4).strip()]
        elif last is not None:
            fields[last][2] += " " + line.strip()
        else:
            raise ValueError(f"bad _spec line: {line!r}")
    return {k: tuple(v) for k, v in fields.items()}


def _numpy_type(text):
    """The class name and whether a list of it, of a field's type text."""
    t = text.replace("| None", "").strip()
    if t.startswith("list[") and t.endswith("]"):
        inner = t[5:-1].strip()
        return inner, True
    return t, False


class Result:
    """A library result: its JSON document's fields as attributes (and as
    items: ``r["key"]`` is ``r.key``).

    Nested objects are Results of their own classes, lists of objects lists
    of them, arrays of numbers read-only NumPy arrays (float64 with NaN where
    the JSON has null, int64, bool; matrices 2-D). Results are read-only:
    to_dict() gives a plain copy to change.

    Methods
    -------
    to_dict()
        The document as json.loads gives it (arrays as lists, NaN as None).
    to_json(indent=1)
        The document as JSON text.
    keys(), items(), values(), get(key, default=None)
        The fields the document holds, as a dict's.
    """

    __slots__ = ("_data",)
    _spec = ""
    _fields = {}
    _fields_own = {}
    _array_fields = frozenset()

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if "__slots__" not in cls.__dict__:
            raise TypeError(f"{cls.__name__}: a Result class declares __slots__")
        own = _parse_spec(cls.__dict__.get("_spec", ""))
        cls._fields_own = own
        cls._fields = {**getattr(cls, "_fields", {}), **own}
        cls._array_fields = frozenset(k for k, (t, _, _) in cls._fields.items()
                                      if t.replace("| None", "").strip() in _ARRAY_TYPES)
        _REGISTRY[cls.__name__] = cls
        if own and cls.__doc__ is not None and "Attributes\n" not in cls.__doc__:
            indent = "    " if "\n" in cls.__doc__.strip() or cls.__doc__.endswith("    ") else ""
            section = _attributes_doc(cls._fields).replace("\n", "\n" + indent)
            cls.__doc__ = cls.__doc__.rstrip() + "\n\n" + indent + section + "\n" + indent

    def __init__(self, data):
        object.__setattr__(self, "_data", data)

    def _field(self, key):
        """The field `key`, its nested objects wrapped in their classes on the
        first access (and kept so): making a result costs one object, however
        large its document."""
        data = self._data
        value = data[key]
        if type(value) is dict or (type(value) is list and value and type(value[0]) in (dict, list)) or \
                (type(value) is list and key in self._array_fields):
            spec = self._fields.get(key)
            value = _wrap(value, spec[0]) if spec is not None else _generic(value)
            data[key] = value
        return value

    def __getattr__(self, key):
        data = object.__getattribute__(self, "_data")
        if key in data:
            return self._field(key)
        if key in type(self)._fields:
            return None  # a field this document does not hold
        raise AttributeError(f"{type(self).__name__} has no '{key}' (it has: {', '.join(data)})")

    def __getitem__(self, key):
        if key not in self._data:
            raise KeyError(key)
        return self._field(key)

    def __contains__(self, key):
        return key in self._data

    def __iter__(self):
        return iter(self._data)

    def __setattr__(self, key, value):
        raise AttributeError("results are read-only: use to_dict() for a copy to change")

    def __dir__(self):
        return sorted(set(self._data) | set(super().__dir__()))

    def __reduce__(self):
        # Pickling and copying (the slots are read-only to setattr).
        state = {}
        for c in type(self).__mro__:
            for name in c.__dict__.get("__slots__", ()):
                try:
                    state[name] = object.__getattribute__(self, name)
                except AttributeError:
                    pass
        return _rebuild, (type(self), state)

    def __eq__(self, other):
        return isinstance(other, Result) and type(other) is type(self) and self.to_dict() == other.to_dict()

    __hash__ = None

    def keys(self):
        """The names of the fields the document holds."""
        return self._data.keys()

    def items(self):
        """(name, value) of the fields the document holds."""
        return [(key, self._field(key)) for key in self._data]

    def values(self):
        """The values of the fields the document holds."""
        return [self._field(key) for key in self._data]

    def get(self, key, default=None):
        """The field `key`, or `default` when the document does not hold it."""
        return self._field(key) if key in self._data else default

    def to_dict(self):
        """The document as plain Python data: what json.loads gives for the
        command's JSON text (lists for the arrays, None for NaN); a copy."""
        return _plain(self._data)

    def to_json(self, indent=1):
        """The document as JSON text (null for NaN)."""
        return json.dumps(self.to_dict(), indent=indent)

    def _summary(self):
        """The text inside repr's parentheses: the first few short fields
        with their values, and how many others there are (subclasses give
        their own)."""
        parts = []
        for key, value in self._data.items():
            if isinstance(value, float):
                parts.append(f"{key}={_fmt(value)}")
            elif value is None or isinstance(value, (bool, int)) or (isinstance(value, str) and len(value) <= 30):
                parts.append(f"{key}={value!r}")
            if len(parts) == 5:
                break
        others = len(self._data) - len(parts)
        return ", ".join(parts) + (f", +{others} fields" if others and parts else f"{others} fields" if others else "")

    def __repr__(self):
        return f"{type(self).__name__}({self._summary()})"


def _rebuild(cls, state):
    """A result of class cls with the slots `state` (unpickling, copying)."""
    out = object.__new__(cls)
    for name, value in state.items():
        object.__setattr__(out, name, value)
    return out


_DOC_TYPES = {"array": "numpy.ndarray of float64", "int_array": "numpy.ndarray of int64",
              "bool_array": "numpy.ndarray of bool", "matrix": "2-D numpy.ndarray of float64",
              "ndarray": "numpy.ndarray"}


def _doc_type(type_text):
    """A field's type in numpydoc's words."""
    out = []
    for part in (p.strip() for p in type_text.split("|")):
        if part.startswith("list[") and part.endswith("]"):
            out.append("list of " + _DOC_TYPES.get(part[5:-1], part[5:-1]))
        else:
            out.append(_DOC_TYPES.get(part, part))
    return " or ".join(out)


def _attributes_doc(fields):
    lines = ["Attributes", "----------"]
    for name, (type_text, optional, meaning) in fields.items():
        t = _doc_type(type_text) + (" or None (absent from some documents)" if optional and "None" not in type_text
                                    else "")
        lines.append(f"{name} : {t}")
        words, row = meaning.split(), "   "
        for w in words:
            if len(row) + len(w) > 100:
                lines.append(row)
                row = "   "
            row += " " + w
        if words:
            lines.append(row)
    return "\n".join(lines)


def _as_array(value, dtype):
    """A list the binding left as a list (empty, or only nulls) as the
    declared array; anything else (a ragged matrix) as it is."""
    if isinstance(value, np.ndarray) or not isinstance(value, list):
        return value
    try:
        a = np.array([np.nan if x is None else x for x in value], dtype=dtype)
    except (TypeError, ValueError):
        return value
    a.flags.writeable = False
    return a


def _wrap(value, type_text):
    if value is None:
        return None
    dtype = _ARRAY_TYPES.get(type_text.replace("| None", "").strip())
    if dtype is not None:
        return _as_array(value, dtype)
    name, is_list = _numpy_type(type_text)
    cls = _REGISTRY.get(name)
    if cls is None:
        return _generic(value)
    if is_list:
        if isinstance(value, list):
            return [cls(v) if isinstance(v, dict) else _generic(v) for v in value]
        return _generic(value)
    return cls(value) if isinstance(value, dict) else _generic(value)


class Node(Result):
    """An object of a document that no class declares (a field added to the
    document after this version of the package): its keys as attributes."""

    __slots__ = ()


def _generic(value):
    if isinstance(value, dict):
        return Node(value)
    if isinstance(value, list):
        return [_generic(v) for v in value]
    return value


def _plain(v):
    if isinstance(v, Result):
        return _plain(v._data)
    if isinstance(v, dict):
        return {k: _plain(x) for k, x in v.items()}
    if isinstance(v, list):
        return [_plain(x) for x in v]
    if isinstance(v, np.ndarray):
        if v.dtype.kind == "f" and np.isnan(v).any():
            return _with_none(v.tolist())
        return v.tolist()
    if isinstance(v, np.generic):
        return v.item()
    return v


def _with_none(v):
    if isinstance(v, list):
        return [_with_none(x) for x in v]
    return None if v != v else v


def _fmt(x, unit=""):
    """A number for a repr: 4 significant digits, with its unit."""
    if x is None:
        return "-"
    text = f"{x:.4g}"
    return f"{text} {unit}" if unit else text


# ---------------------------------------------------------------------------
# Kinds that several documents share.


class Quantity(Result):
    """A value with its 1-sigma uncertainty and its unit."""

    __slots__ = ()
    _spec = """
    value: float | None -- the value, in `unit` (None where the data do not determine it)
    sigma: float | None -- its 1-sigma uncertainty, in `unit` (None: none, or an upper bound)
    unit: str -- the unit of value and sigma (e.g. "deg/sqrt(h)", "deg/h")
    """

    def _summary(self):
        s = "" if self.sigma is None else f" +- {_fmt(self.sigma)}"
        return f"{_fmt(self.value)}{s} {self.unit}"


class Misalignment(Result):
    """Misalignment angles by axis pair: key ij, the angle by which axis i leans toward axis j."""

    __slots__ = ()
    _spec = """
    xy: float -- x toward y
    xz: float -- x toward z
    yx: float -- y toward x
    yz: float -- y toward z
    zx: float -- z toward x
    zy: float -- z toward y
    """


class AllanCurve(Result):
    """An overlapping Allan deviation curve with its confidence intervals."""

    __slots__ = ()
    _spec = """
    af?: int_array -- averaging factors m (tau = m / rate)
    m?: int_array -- averaging factors m (turnon and compare name them m)
    tau: array -- averaging times, s
    dev: array -- the deviation at each tau, in the channel's unit
    n: int_array -- the number of terms behind each point
    lo?: array -- lower end of the confidence interval at ci, in the channel's unit
    hi?: array -- upper end of the confidence interval at ci, in the channel's unit
    edf?: array -- equivalent degrees of freedom of each point
    alpha?: int_array -- the power-law noise type identified at each tau (+2 .. -2)
    """

    def _summary(self):
        if len(self.tau) == 0:
            return "no taus"
        return f"{len(self.tau)} taus, {_fmt(self.tau[0])} .. {_fmt(self.tau[-1])} s"


class ExcludedTau(Result):
    """A tau of a listed grid left out of a curve, and why."""

    __slots__ = ()
    _spec = """
    tau_s: float -- the tau asked for, s
    af: int | float -- its averaging factor
    needs_samples: int | float -- the samples it needs
    samples: int -- the samples there are
    reason: str -- why it was left out
    """


class MergedTau(Result):
    """A tau of a listed grid that fell on the averaging factor of an earlier one."""

    __slots__ = ()
    _spec = """
    tau_s: float -- the tau asked for, s
    merged_with_tau_s: float -- the tau it was merged with, s
    af: int -- their averaging factor
    """


class ModelQuantityDisplay(Result):
    """A model quantity in the unit engineers quote it in."""

    __slots__ = ()
    _spec = """
    value: float -- the value, in `unit`
    sigma: float | None -- the bootstrap's standard deviation, in `unit` (None without bootstrap)
    lo: float | None -- the bootstrap interval's lower end at ci, in `unit`
    hi: float | None -- its upper end, in `unit`
    asymptotic_sd: float | None -- the GMWM's sandwich standard deviation, in `unit` (None where the fit does
        not determine it)
    unit: str -- the display unit (e.g. "deg/sqrt(h)")
    """


class ModelQuantity(Result):
    """A physical quantity of a composite-model term (N, sigma_b, T, ...)."""

    __slots__ = ()
    _spec = """
    name: str -- the quantity's name (N, K, B, sigma_b, T, Q, ...)
    value: float -- its value, in `unit`
    unit: str -- its unit (from the channel's unit and the sampling rate)
    sd: float | None -- the parametric bootstrap's standard deviation, in `unit` (None without bootstrap)
    lo: float | None -- the bootstrap interval's lower end at ci, in `unit`
    hi: float | None -- its upper end, in `unit`
    asymptotic_sd: float | None -- the sandwich standard deviation by the delta method, in `unit`
    display: ModelQuantityDisplay -- the same in the display unit
    """

    def _summary(self):
        return f"{self.name} = {_fmt(self.value, self.unit)}"


class ModelParameters(Result):
    """The GMWM parameters of a composite-model term, per sample."""

    __slots__ = ()
    _spec = """
    value: float -- the term's variance parameter, in the channel's unit squared (per sample)
    phi?: float -- GM: the autoregressive coefficient (1)
    theta?: float -- MA1: the moving-average coefficient (1)
    omega?: float -- SIN: the angular frequency, rad per sample
    """


class ModelTerm(Result):
    """A term of a composite noise model (WN, QN, RW, DR, GM, MA1, SIN, ...)."""

    __slots__ = ()
    _spec = """
    term: str -- the term's kind (WN, QN, RW, DR, GM, MA1, SIN)
    parameters: ModelParameters -- its GMWM parameters
    quantities: list[ModelQuantity] -- the physical quantities it stands for
    """

    def _summary(self):
        return self.term + ": " + ", ".join(q._summary() for q in self.quantities)


class ModelCandidate(Result):
    """A candidate model ranked by the Wavelet Information Criterion."""

    __slots__ = ()
    _spec = """
    model: str -- the candidate (e.g. "WN+RW+GM")
    parameters: int -- its number of parameters
    wic: float -- its WIC (loss + optimism; lower is better)
    loss: float -- the GMWM objective at the fit
    optimism: float -- the WIC's optimism term
    replicates: int -- bootstrap replicates behind the optimism (0: the asymptotic form)
    objective: float -- the GMWM objective
    """


class WaveletVariance(Result):
    """A channel's Haar wavelet variance, its intervals and the model's."""

    __slots__ = ()
    _spec = """
    tau_samples: array -- scales, samples
    tau_s: array -- scales, s
    nu2: array -- the Haar wavelet variance, in the channel's unit squared
    lo: array -- lower end of its interval at ci, unit squared
    hi: array -- upper end, unit squared
    edf: array -- equivalent degrees of freedom
    n: int_array -- wavelet coefficients at each scale
    model: array -- the fitted model's wavelet variance, unit squared
    """


class SpectralLine(Result):
    """A periodic line of a channel's spectrum (a SIN term of its twin)."""

    __slots__ = ()
    _spec = """
    frequency_hz: float -- its frequency, Hz
    power: float -- its power, in the channel's unit squared
    amplitude: float -- its amplitude sqrt(2 power), in the channel's unit
    peak_ratio: float -- its peak over the spectrum's background
    width_hz: float -- its width, Hz
    """


class TwinFidelity(Result):
    """How well a twin reproduces the wavelet variance."""

    __slots__ = ()
    _spec = """
    scales: int -- the scales compared
    inside_95: int -- scales where the model lies inside the 95 % interval
    share_inside: float -- their share (0 to 1)
    max_error: float -- the largest relative error of the model's wavelet variance
    max_error_tau_s: float -- the scale of that error, s
    faithful: bool -- whether the twin is judged faithful
    """


class TwinError(Result):
    """The twin's error on the measured Allan curve."""

    __slots__ = ()
    _spec = """
    taus: int -- the taus compared
    inside: int -- taus where the twin's deviation lies inside the measured interval
    share_inside: float -- their share (0 to 1)
    max_error: float -- the largest |twin / measured - 1|
    max_error_tau_s: float -- the tau of that error, s
    max_error_10s?: float | None -- the largest error up to 10 s
    max_error_100s?: float | None -- the largest error up to 100 s
    note: str -- how it is computed
    """


class ModelChannel(Result):
    """A channel's composite noise model fitted by the GMWM (cubecal model)."""

    __slots__ = ()
    _spec = """
    name: str -- the channel
    unit: str | None -- its unit (None: none given)
    model: str -- the model fitted (the selected one among candidates)
    candidates: list[ModelCandidate] -- the candidates ranked by the WIC (with several)
    failed: list[str] -- candidates without a fit or a score, and why
    objective: float -- the GMWM objective at the fit
    converged: bool -- whether the optimiser converged
    replicates: int -- bootstrap replicates behind the uncertainties (0: none)
    terms: list[ModelTerm] -- the model's terms with their quantities
    wavelet_variance: WaveletVariance -- the wavelet variance fitted and the model's
    lines?: list[SpectralLine] -- the spectrum's lines (a twin's search)
    lines_error?: str -- why the lines could not be searched
    fidelity?: TwinFidelity -- the twin's fidelity on the wavelet variance
    residual_rms_log?: float -- rms of log(model / measured) over the Allan curve (analyze)
    residual_chi2?: float -- chi-squared of the model over the Allan curve (analyze)
    twin_error?: TwinError -- the twin's error on the Allan curve (analyze)
    """

    def _summary(self):
        return f"{self.name!r}, {self.model}: " + "; ".join(t._summary() for t in self.terms)
