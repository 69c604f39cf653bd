"""The platforms mechfmu builds FMUs for, and this machine's: its FMI 3.0 platform tuple
(:data:`NATIVE`), the folder of its binaries in an FMU (:data:`HOST_FOLDER`) and the file
extension of its shared libraries (:data:`HOST_EXTENSION`)."""

from __future__ import annotations

import platform as _platform_info

__all__ = ["PLATFORMS", "NATIVE", "HOST_FOLDER", "HOST_EXTENSION", "binary_folders", "library_extension"]

#: FMI 3.0's platform tuples of the platforms mechfmu builds FMUs for
PLATFORMS = ("x86_64-linux", "x86_64-windows", "aarch64-linux", "x86_64-darwin", "aarch64-darwin")


def _this_platform() -> str:
    """This machine's FMI 3.0 platform tuple (``x86_64-linux``, ``aarch64-darwin``, ...)."""
    machine = _platform_info.machine().lower()
    arch = {"amd64": "x86_64", "arm64": "aarch64"}.get(machine, machine)
    system = {"Darwin": "darwin"}.get(_platform_info.system(), _platform_info.system().lower())
    return f"{arch}-{system}"


#: the platform this module runs on (its binary runs under every importer)
NATIVE = _this_platform()


def binary_folders(platform: str) -> dict[str, str]:
    """The folder under ``binaries/`` FMPy loads a binary for ``platform`` from, by FMI major
    version: FMI 2.0's x86-64 names, and on Apple silicon ``darwin64`` (whose universal file
    mechfmu makes for it), else the FMI 3.0 tuple."""
    fmi2 = {"x86_64-linux": "linux64", "x86_64-windows": "win64", "x86_64-darwin": "darwin64",
            "aarch64-darwin": "darwin64"}
    return {"2": fmi2.get(platform, platform), "3": platform}


def library_extension(platform: str) -> str:
    """The file extension of a shared library of ``platform``."""
    return {"windows": "dll", "darwin": "dylib"}.get(platform.partition("-")[2], "so")


#: this machine's binary folder, by FMI major version
HOST_FOLDER = binary_folders(NATIVE)
#: the file extension of this machine's shared libraries
HOST_EXTENSION = library_extension(NATIVE)
