"""``yade.libVersions``: the versions of the libraries granum runs on.

YADE reports each library twice: as cmake found it when YADE was built, and as the compiled C++ code
sees it at run time. granum is not built ahead, so its two sources are the nearest counterparts:

- :func:`getAllVersionsCmake`: the version the installer recorded (the distribution's metadata);
- :func:`getAllVersionsCpp`: the version the imported module reports (``module.__version__``; for
  ``python`` the interpreter, for ``compiler`` the LLVM inside llvmlite that Numba compiles with).

Both give ``{name: [(major, minor, patch), "text"]}`` as YADE does, so a mismatch between the
installed and the imported copy of a library shows up the same way.
"""

from __future__ import annotations

import importlib
import importlib.metadata
import platform
import re
import sys

#: library name -> (distribution name, module name) for the libraries granum imports
LIBRARIES = {
    "numpy": ("numpy", "numpy"),
    "numba": ("numba", "numba"),
    "llvmlite": ("llvmlite", "llvmlite"),
    "matplotlib": ("matplotlib", "matplotlib"),
    "pillow": ("pillow", "PIL"),
    "imageio-ffmpeg": ("imageio-ffmpeg", "imageio_ffmpeg"),
    "h5py": ("h5py", "h5py"),
    "dask": ("dask", "dask"),
    "distributed": ("distributed", "distributed"),
    "bokeh": ("bokeh", "bokeh"),
    "filelock": ("filelock", "filelock"),
    "ipython": ("ipython", "IPython"),
}

#: Debian's names of processor architectures (the names YADE reports), by ``uname -m``
_DEBIAN_ARCHITECTURES = {"x86_64": "amd64", "aarch64": "arm64", "i686": "i386", "i386": "i386",
                         "ppc64le": "ppc64el", "s390x": "s390x", "armv7l": "armhf"}


def _version_entry(text: str) -> list:
    """``[(major, minor, patch), text]``: the first three numbers of ``text`` (missing ones are 0)."""
    numbers = [int(n) for n in re.findall(r"\d+", text)[:3]]
    return [tuple(numbers + [0] * (3 - len(numbers))), text]


def getAllVersionsCmake() -> dict:
    """The versions of the installed distributions (YADE: as cmake found them at build time)."""
    found = {"python": _version_entry(platform.python_version())}
    for name, (distribution, _) in LIBRARIES.items():
        try:
            found[name] = _version_entry(importlib.metadata.version(distribution))
        except importlib.metadata.PackageNotFoundError:
            continue
    return found


def _imported_version(name: str):
    """The version entry the imported module of a library reports, or None."""
    if name == "python":
        return _version_entry(platform.python_version())
    if name == "compiler":
        import llvmlite.binding

        llvm = tuple(llvmlite.binding.llvm_version_info)
        return [llvm, "llvm " + ".".join(str(n) for n in llvm)]
    try:
        module = importlib.import_module(LIBRARIES[name][1])
    except (KeyError, ImportError):
        return None
    text = getattr(module, "__version__", None)
    return _version_entry(text) if isinstance(text, str) else None


def getAllVersionsCpp() -> dict:
    """The versions the imported modules report (YADE: as its C++ code sees them at run time)."""
    found = {name: _imported_version(name) for name in ("python", "compiler", *LIBRARIES)}
    return {name: entry for name, entry in found.items() if entry is not None}


def getVersion(libName: str):
    """``(major, minor, patch)`` of a library, from the imported module, else from the installed
    distribution; None for a library granum does not use or cannot find."""
    entry = _imported_version(libName) or getAllVersionsCmake().get(libName)
    return entry[0] if entry else None


def getArchitecture() -> str:
    """The processor architecture in Debian's naming, as YADE reports it (``amd64``, ``arm64``...)."""
    machine = platform.machine()
    return _DEBIAN_ARCHITECTURES.get(machine, machine)


def getLinuxVersion() -> str:
    """The operating system: ``PRETTY_NAME`` of ``/etc/os-release`` where there is one, else
    ``platform.platform()``."""
    try:
        return platform.freedesktop_os_release()["PRETTY_NAME"]
    except (OSError, KeyError):
        return platform.platform()


def _table(rows: list[tuple[str, str, str]], rst: bool) -> list[str]:
    widths = (14, 21, 19)

    def line(cells):
        return "| " + " | ".join(c.ljust(w) for c, w in zip(cells, widths, strict=True)) + " |"
    header = line(("library", "installed", "imported"))
    if rst:
        rule = "+" + "+".join("-" * (w + 2) for w in widths) + "+"
        out = [rule, header, rule.replace("-", "=")]
        for row in rows:
            out += [line(row), rule]
        return out
    return [header, "| " + " | ".join("-" * w for w in widths) + " |"] + [line(row) for row in rows]


def getAllVersions(rstFormat: bool = False) -> str:
    """The text :func:`printAllVersions` prints."""
    from granum.yade import config

    precision = (f"{sys.float_info.mant_dig} bits, {config.highPrecisionDecimalPlaces} decimal places, "
                 f"{'with' if config.highPrecisionMpmath else 'without'} mpmath, {config.highPrecisionName}")
    summary = [f"granum version:  {config.version}",
               f"granum features:  {' '.join(config.features)}",
               f"granum config dir:  {config.confDir}",
               f"granum precision:  {precision}"]
    installed, imported = getAllVersionsCmake(), getAllVersionsCpp()
    rows = [(name, installed.get(name, [None, ""])[1], imported.get(name, [None, ""])[1])
            for name in sorted(set(installed) | set(imported))]
    system = [f"Linux version  :  {getLinuxVersion()}", f"Architecture   :  {getArchitecture()}",
              f"Little endian  :  {sys.byteorder == 'little'}"]
    fence = [] if rstFormat else ["```"]
    lines = fence + summary + fence + ["", "Libraries used :", ""] + _table(rows, rstFormat) + [""]
    lines += fence + system + fence
    return "\n".join(lines) + "\n"


def printAllVersions(rstFormat: bool = False) -> None:
    """Print granum's version, features and the versions of its libraries, as a Markdown table, or as a
    reStructuredText grid table when ``rstFormat`` is True."""
    print(getAllVersions(rstFormat))
