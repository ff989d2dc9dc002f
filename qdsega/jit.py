"""numba compilation without reference counting, for helpers called at every step."""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

from numba import njit
from numba.core.dispatcher import Dispatcher

_Function = TypeVar("_Function", bound=Callable[..., object])


def njit_no_refcount(*, fastmath: bool = False) -> Callable[[_Function], Dispatcher[_Function]]:
    """``njit(cache=True)`` with numba's reference counting off (``_nrt=False``).

    numba would otherwise incref and decref every array such a helper is passed, an atomic
    operation each; a helper compiled so must not allocate arrays.
    """
    # _nrt is an option numba reads but its type stubs leave out of njit's keywords.
    return njit(cache=True, fastmath=fastmath, _nrt=False)  # type: ignore[call-overload]
