"""cubecal.read: every format the CLI reads, into NumPy arrays."""
import os

from . import _args, _cubecal
from ._data import number_list, string_list


class Record(dict):
    """Columns of a record read by cubecal.read, with what the reader found out.

    A dict of name -> 1-D float64 array, in file order (the time column
    first when there is one, in s; the channels in their units).

    Attributes
    ----------
    file : str
        The record's path.
    rate_hz : float
        The sampling rate, Hz (given, or from the time stamps).
    rate_from_time : bool
        Whether the rate comes from the time stamps.
    time : str
        The time column's name ("" : none).
    channels : list of str
        The channel names.
    extra : list of str
        Further columns asked for (extra=).
    units : list of str
        The units the format states (ROS messages; else empty).
    left_out : list of str
        Columns or fields left out.
    topics : list of str
        The ROS topics read.
    segments : list of (int, int)
        (begin, end) sample ranges; several when split at gaps.
    gaps : str
        As read: "error", "split" or "skip".
    missing_samples : list of int
        NaN per channel (gaps="skip").
    bytes : int
        Bytes read.
    """

    def __init__(self, columns, meta):
        super().__init__(columns)
        for key, value in meta.items():
            setattr(self, key, value)

    def __repr__(self):
        return f"Record({self.file!r}, {len(next(iter(self.values()), []))} samples at {self.rate_hz:g} Hz, " \
               f"columns {list(self)})"


def read_args(columns=None, time=None, rate=None, skip_rows=0, lsb=None, gaps="error", topics=None, dataset=None,
              binary=None, header_bytes=0, extra=None, threads=0):
    """The reader's arguments of cubecal.read (and of the calls that read a
    path), checked and named as the CLI's input options.

    Parameters
    ----------
    columns, time, rate, skip_rows, lsb, gaps, topics, dataset, binary, header_bytes, extra, threads
        As cubecal.read's (rate in Hz).

    Returns
    -------
    cubecal._cubecal._ReadArgs
        The arguments for the binding.
    """
    a = _cubecal._ReadArgs()
    a.columns = string_list(columns, "columns")
    if time is not None and (isinstance(time, bool) or not isinstance(time, (str, int))):
        raise _args.usage("time", f"time: the name or 1-based index of the time column, not {time!r}")
    a.time = str(time) if time is not None else ""
    a.rate = _args.rate(rate) if rate is not None else 0.0
    a.skip_rows = _args.count(skip_rows, "skip_rows")
    a.lsb = number_list(lsb, "lsb")
    a.gaps = _args.text(gaps, "gaps")
    a.topics = string_list(topics, "topics")
    a.dataset = _args.optional_text(dataset, "dataset") or ""
    a.binary = _args.optional_text(binary, "binary") or ""
    a.header_bytes = _args.count(header_bytes, "header_bytes")
    a.extra = string_list(extra, "extra")
    a.threads = _args.threads(threads)
    return a


@_args.public
def read(path, columns=None, time=None, rate=None, skip_rows=0, lsb=None, gaps="error", topics=None, dataset=None,
         binary=None, header_bytes=0, extra=None, frame=False, threads=0):
    """Reads and checks a record as the CLI does.

    Delimited text (.csv, .gz), NumPy .npy, HDF5, ROS 1 bags, MCAP and
    rosbag2, PX4 ULog, or raw frames.

    Parameters
    ----------
    path : str or os.PathLike
        The record.
    columns : str or list, optional
        Names or 1-based indices (default: every column but time,
        temperature and extra).
    time : str or int, optional
        The time column (default: found by name).
    rate : float, optional
        Sampling rate, Hz (default: from the time column).
    skip_rows : int
        Lines of preamble.
    lsb : float or list of float, optional
        Counts per unit, one for all or one per column.
    gaps : str
        "error", "split" or "skip" (an empty field or NaN is a missing
        sample, NaN in the arrays, and a gap of whole periods in the time
        stamps is filled with them, as the CLI's --gaps skip).
    topics : str or list of str, optional
        ROS topics.
    dataset : str, optional
        The HDF5 dataset.
    binary : str, optional
        Raw frames: "float64le,int16le,..." (with rate=).
    header_bytes : int
        Bytes before the first raw frame.
    extra : str or list of str, optional
        Further columns read as they are (e.g. a temperature).
    frame : bool
        Return a pandas DataFrame.
    threads : int
        Worker threads (0: every core).

    Returns
    -------
    Record or pandas.DataFrame
        A dict of 1-D float64 arrays (in their units; time in s) with the
        reader's findings as attributes.

    Raises
    ------
    cubecal.InputError
        Bad data, with .file, .line and .column.
    """
    args = read_args(columns, time, rate, skip_rows, lsb, gaps, topics, dataset, binary, header_bytes, extra,
                     threads)
    frame = _args.flag(frame, "frame")
    columns_read, meta = _cubecal._read(_args.path(path), args)
    record = Record(columns_read, meta)
    if not frame:
        return record
    try:
        import pandas
    except ImportError as e:
        raise ImportError("cubecal.read(frame=True) needs pandas (Debian: python3-pandas)") from e
    return pandas.DataFrame(dict(record))
