"""JSON helpers shared by the shape and sequence files: parsing with line numbers."""

import json
import numbers

import numpy as np

from ..errors import FileFormatError
from ._files import read_text

__all__ = ["JsonDocument", "dumps_rows", "dumps_finite", "first_non_finite"]

_DECODER = json.JSONDecoder()
_WS = " \t\n\r"

_MAX_INDEX = 2**62
_MAX_FLOAT = 1.7e308  # finite doubles (inf and nan compare False, huge ints too)

#: deepest nesting of arrays and objects read (isotween files need 4)
MAX_DEPTH = 64


class _Depth(int):
    """Maximum nesting depth, with the line where it was first exceeded."""

    line = 1


def _nesting(text):
    """Deepest bracket nesting of a JSON text outside strings (vectorised scan).

    Returns
    -------
    _Depth
        With ``line``: where the depth first exceeds `MAX_DEPTH` (or 1).
    """
    raw = np.frombuffer(text.encode("utf-8", "surrogatepass"), dtype=np.uint8)
    if not raw.size:
        return _Depth(0)
    # characters inside strings: between unescaped quotes
    quote = raw == ord('"')
    backslash = raw == ord("\\")
    if backslash.any():
        # a quote is escaped when preceded by an odd run of backslashes
        idx = np.flatnonzero(quote)
        run = np.zeros(len(idx), dtype=np.int64)
        prev = idx - 1
        active = prev >= 0
        while active.any():
            hit = np.zeros(len(idx), dtype=bool)
            hit[active] = backslash[prev[active]]
            run += hit
            prev = prev - 1
            active = hit & (prev >= 0)
        quote[idx[run % 2 == 1]] = False
    inside = (np.cumsum(quote) % 2 == 1) & ~quote
    step = np.where(inside, 0,
                    (raw == ord("[")).astype(np.int64) + (raw == ord("{")) - (raw == ord("]")) - (raw == ord("}")))
    level = np.cumsum(step)
    depth = _Depth(int(level.max(initial=0)))
    if depth > MAX_DEPTH:
        depth.line = int(np.count_nonzero(raw[: int(np.argmax(level > MAX_DEPTH))] == ord("\n"))) + 1
    return depth


class JsonDocument:
    """A parsed JSON file that can say on which line an element starts.

    Parameters
    ----------
    path : path-like

    Attributes
    ----------
    data : object
        The decoded document.
    """

    def __init__(self, path):
        self.path = path
        self.text = read_text(path)
        depth = _nesting(self.text)
        if depth > MAX_DEPTH:
            raise FileFormatError(f"{path}, line {depth.line}: JSON nested deeper than {MAX_DEPTH} levels")
        try:
            self.data = json.loads(self.text)
        except json.JSONDecodeError as exc:
            raise FileFormatError(f"{path}, line {exc.lineno}: invalid JSON: {exc.msg}") from None
        except (RecursionError, MemoryError):
            raise FileFormatError(f"{path}: JSON nested too deeply or too large to read") from None
        except ValueError as exc:  # e.g. an integer with too many digits
            raise FileFormatError(f"{path}: invalid JSON: {exc}") from None

    # ------------------------------------------------------------ locating
    def _skip_ws(self, pos):
        while pos < len(self.text) and self.text[pos] in _WS:
            pos += 1
        return pos

    def line_of(self, *keys):
        """Line (1-based) where the element at ``keys`` (object keys, list indices) starts."""
        pos = self._skip_ws(0)
        for key in keys:
            opener = self.text[pos]
            pos = self._skip_ws(pos + 1)
            if opener == "{":
                while self.text[pos] != "}":
                    name, pos = _DECODER.raw_decode(self.text, pos)
                    pos = self._skip_ws(self._skip_ws(pos) + 1)  # past ':'
                    if name == key:
                        break
                    pos = self._after_value(pos)
                else:
                    break
            elif opener == "[":
                for _ in range(key):
                    pos = self._after_value(pos)
            else:
                break
        return self.text.count("\n", 0, pos) + 1

    def _after_value(self, pos):
        _, end = _DECODER.raw_decode(self.text, pos)
        end = self._skip_ws(end)
        return self._skip_ws(end + 1) if self.text[end] == "," else end

    def error(self, message, *keys):
        """`FileFormatError` naming the file, the line of ``keys`` and the element."""
        where = "".join(f"[{k}]" if isinstance(k, int) else (f".{k}" if i else k) for i, k in enumerate(keys))
        return FileFormatError(f"{self.path}, line {self.line_of(*keys)}: {where}: {message}")

    # ------------------------------------------------------------ validating
    def require_object(self):
        if not isinstance(self.data, dict):
            raise FileFormatError(f"{self.path}, line 1: expected a JSON object {{...}} at the top")
        return self.data

    def array(self, key, width, kind, required=False, container=None, keys=()):
        """Validate ``container[key]`` as a list of ``width``-long rows of ``kind`` numbers.

        Parameters
        ----------
        key : str or int
        width : int or None
            Row length, or None for a flat list.
        kind : {'float', 'int'}
        required : bool
        container : dict, optional
            Object holding ``key`` (the top level by default).
        keys : tuple
            Where ``container`` sits in the document (for line numbers).

        Returns
        -------
        ndarray or None
            (k, width) or (k,) array; None when absent and not required.
        """
        container = self.data if container is None else container
        where = keys + (key,)
        present = key < len(container) if isinstance(container, list) else key in container
        if not present or container[key] is None:
            if required:
                raise self.error(f"missing the required key '{key}'", *keys) if keys else FileFormatError(
                    f"{self.path}, line 1: missing the required key '{key}'"
                )
            return None
        rows = container[key]
        if not isinstance(rows, list):
            raise self.error("expected a list", *where)
        number = numbers.Integral if kind == "int" else numbers.Real
        for i, row in enumerate(rows):
            items = row if width is not None else [row]
            if width is not None and (not isinstance(row, list) or len(row) != width):
                raise self.error(f"expected a list of {width} numbers, got {json.dumps(row)}", *where, i)
            if not all(isinstance(x, number) and not isinstance(x, bool) for x in items):
                what = "integers" if kind == "int" else "numbers"
                raise self.error(f"expected {what}, got {json.dumps(row)}", *where, i)
            if kind == "int" and not all(abs(x) <= _MAX_INDEX for x in items):
                raise self.error(f"index out of range in {json.dumps(row)[:80]}", *where, i)
            if kind != "int" and not all(abs(x) <= _MAX_FLOAT for x in items):
                raise self.error(f"non-finite or too large value in {json.dumps(row)[:80]}", *where, i)
        dtype = np.int64 if kind == "int" else np.float64
        shape = (len(rows), width) if width is not None else (len(rows),)
        return np.array(rows, dtype=dtype).reshape(shape)


def dumps_rows(rows, indent="  "):
    """A JSON list written one row per line (floats as shortest round-trip decimals)."""
    if not len(rows):
        return "[]"
    body = f",\n{indent}  ".join(json.dumps(r) for r in rows)
    return f"[\n{indent}  {body}\n{indent}]"


def first_non_finite(value, where=""):
    """Where the first NaN or infinity in nested lists, dicts and arrays sits, or None.

    Parameters
    ----------
    value : object
        JSON-ready data (dicts, lists, tuples, numbers, numpy arrays).
    where : str
        Name of ``value`` itself, as the result starts.

    Returns
    -------
    (str, float) or None
        ``('paint[0].width[2]', inf)`` style location and the value.
    """
    if isinstance(value, float | np.floating):
        return None if np.isfinite(value) else (where or "value", float(value))
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "fc" and not np.all(np.isfinite(value)):
            k = np.argwhere(~np.isfinite(value))[0]
            return f"{where}" + "".join(f"[{int(i)}]" for i in k), float(np.real(value[tuple(k)]))
        return None
    if isinstance(value, dict):
        items = ((f"{where}.{k}" if where else str(k), v) for k, v in value.items())
    elif isinstance(value, list | tuple):
        items = ((f"{where}[{i}]", v) for i, v in enumerate(value))
    else:
        return None
    for name, item in items:
        found = first_non_finite(item, name)
        if found is not None:
            return found
    return None


def dumps_finite(data, path, **options):
    """``json.dumps(data)`` that refuses NaN and infinity (JSON has neither) with a clear error.

    Parameters
    ----------
    data : object
    path : path-like or str
        The file being written (named by the error).
    **options
        Passed to `json.dumps` (``separators``, ``indent``, ...).

    Returns
    -------
    str

    Raises
    ------
    FileFormatError
        Naming the file, the element and its value.
    """
    try:
        return json.dumps(data, allow_nan=False, **options)
    except ValueError:
        found = first_non_finite(data)
        where, value = found if found is not None else ("a value", float("nan"))
        raise FileFormatError(f"cannot write {path}: {where} is {value}, and JSON holds finite numbers only "
                              "(a coordinate, width or time too large or undefined)") from None
