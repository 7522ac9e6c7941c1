"""Modules that are also their main function: ``isotween.batch`` is the module and calls `batch`.

`isotween.interpolate`, `isotween.compare`, `isotween.transfer` and
`isotween.batch` name both a module and the function it defines. Importing a submodule binds its name on the
package, so a function re-exported under the module's name would be replaced by
the module (or would hide it: ``import isotween.batch as b`` gave the function).
Instead the module is made callable: ``isotween.batch(...)`` calls
``isotween.batch.batch(...)``, and ``import isotween.batch as b`` gives the module.
"""

import inspect
import sys
import types

__all__ = ["make_callable"]


class _CallableModule(types.ModuleType):
    """A module whose call is the call of its function of the same name."""

    def _function(self):
        return getattr(self, self.__name__.rpartition(".")[2])

    def __call__(self, *args, **kwargs):
        return self._function()(*args, **kwargs)

    @property
    def __signature__(self):
        return inspect.signature(self._function())


def make_callable(name):
    """Make module ``name`` callable as its function of the same last name.

    Parameters
    ----------
    name : str
        A module's ``__name__``, e.g. ``'isotween.batch'``, that defines a
        function named ``batch``.

    Examples
    --------
    >>> import isotween
    >>> import isotween.interpolate as module
    >>> callable(module) and module is isotween.interpolate
    True
    """
    sys.modules[name].__class__ = _CallableModule
