"""Imports every command module so that each registers itself on the group."""
from . import batch  # noqa: F401
from . import compare  # noqa: F401
from . import demo  # noqa: F401
from . import edit  # noqa: F401
from . import info  # noqa: F401
from . import interpolate  # noqa: F401
from . import keyframes  # noqa: F401
from . import prepare  # noqa: F401
from . import render  # noqa: F401
from . import transfer  # noqa: F401
