"""The C++ SDK inside the installed package, found as pybind11's is:

    cmake -S app -B build -Dvwg_DIR="$(python -c 'import vwg; print(vwg.get_cmake_dir())')"
    python -m vwg --cmake-dir          # the same folder

It holds vwg's headers, the static libraries of the components that need no third-party headers
(core: the model, text form, events, actors, η/π/φ, engine and generators; geometry; platform) and
vwgConfig.cmake; ``find_package(vwg REQUIRED COMPONENTS core)`` then links ``vwg::core``. The other
components need the headers of Box2D, OpenCV, OMPL, Eigen or AprilTag: build vwg from source for them.
"""

from __future__ import annotations

from pathlib import Path

from vwg.errors import Error

__all__ = ["get_cmake_dir", "get_include"]

_SDK = Path(__file__).resolve().parent / "sdk"


def _sdk_dir(part: str) -> Path:
    folder = _SDK / part
    if not folder.is_dir():
        raise Error(f"{folder}: this vwg has no C++ SDK (it runs from a source tree, not from an installed wheel "
                    "or `pip install .`); install it, or build vwg with CMake and `cmake --install`")
    return folder


def get_cmake_dir() -> str:
    """The folder of vwgConfig.cmake (give it to CMake as vwg_DIR)."""
    return str(_sdk_dir("cmake"))


def get_include() -> str:
    """The folder of vwg's C++ headers (``#include "vwg/engine.hpp"``)."""
    return str(_sdk_dir("include"))
