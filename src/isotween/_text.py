"""Text from users and files, made safe for where it goes: a terminal line, or a document.

File names, titles and SVG ids can hold anything: newlines, escape sequences,
bytes that are not UTF-8 (Python keeps them as lone surrogates). `safe_text`
makes such text one printable line; `document_text` makes it valid in an
XML, HTML or JSON document (UTF-8 encodable, no control characters).
"""

import re

__all__ = ["safe_text", "document_text"]

# C0 and C1 control characters (tab included), DEL, and the line/paragraph separators
_CONTROL = re.compile("[\x00-\x1f\x7f-\x9f\u2028\u2029]")
# lone surrogates: bytes that were not UTF-8 (os.fsdecode's surrogateescape)
_SURROGATE = re.compile("[\ud800-\udfff]")
# characters XML 1.0 does not allow at all (tab, newline and return are allowed)
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ufffe\uffff\ud800-\udfff]")


def _escape(match):
    code = ord(match.group())
    if 0xDC80 <= code <= 0xDCFF:  # an undecodable byte kept by surrogateescape
        return f"\\x{code - 0xDC00:02x}"
    return {"\n": "\\n", "\r": "\\r", "\t": "\\t"}.get(match.group(), f"\\x{code:02x}" if code < 0x100 else
                                                        f"\\u{code:04x}")


def safe_text(text):
    r"""``text`` as one printable line: control characters and undecodable bytes escaped.

    Parameters
    ----------
    text : object
        Anything; non-strings go through ``str``.

    Returns
    -------
    str
        No newline, no terminal escape sequence, encodable as UTF-8
        (``'a\nb'`` for a newline, ``'\x1b'`` for ESC, ``'\xff'`` for a byte
        that was not UTF-8).

    Examples
    --------
    >>> safe_text("bad\nerror: forged\x1b[2J")
    'bad\\nerror: forged\\x1b[2J'
    """
    text = str(text)
    return _SURROGATE.sub(_escape, _CONTROL.sub(_escape, text))


def document_text(text):
    r"""``text`` fit for a title in an SVG, HTML or JSON document.

    Undecodable bytes become U+FFFD, characters XML does not allow are
    dropped, and line breaks and tabs become spaces (a title is one line).

    Examples
    --------
    >>> document_text("a\x00b\ud8ffc\nd")
    'ab\ufffdc d'
    """
    text = _SURROGATE.sub("\ufffd", str(text))
    text = _NOT_XML.sub("", text)
    return re.sub("[\t\n\r\x7f-\x9f\u2028\u2029]", " ", text)
