"""Container formats of granum checkpoints: one data model, one encoder per file extension.

A checkpoint is a *manifest* -- a tree of plain JSON values (``meta``, see
:mod:`granum.io.checkpoint` for what it holds) -- plus named NumPy arrays. This module stores
that pair in a file and reads it back, verifying everything it reads; it knows nothing about
scenes.

Formats, chosen from the file name when writing and from the content when reading:

``.yade`` (and any other name)
    A zip archive (stored, not compressed): ``granum.json`` holds the header below, each array
    is ``arrays/<name>.npy`` in NumPy's ``.npy`` format. Member dates are fixed, so saving the
    same scene twice gives identical files.
``.xml``
    An XML document ``<granum-checkpoint format= version= digest=>`` with ``<meta>``, the
    manifest as elements (``<object>``, ``<list>``, ``<str>``, ``<int>``, ``<float>``,
    ``<bool>``, ``<null>``; members of an object carry ``key=``), and ``<arrays>``, one
    ``<array name= dtype= shape= sha256=>`` element per array with its bytes in base64.
``.h5``, ``.hdf5``
    HDF5 (h5py): the header as JSON in the root attribute ``granum-checkpoint``, each array as
    the dataset ``arrays/<name>``.
``.gz``, ``.bz2`` (trailing)
    The format named before it, compressed: ``scene.xml.bz2``, ``scene.h5.gz``; a bare
    ``scene.gz`` is a ``.yade`` zip inside gzip (YADE also accepts these extensions).

Header: ``{"format": "granum-checkpoint", "version": 1, "digest": ..., "arrays": {name:
{"dtype", "shape", "sha256"}}, "meta": ...}``. ``digest`` is the SHA-256 of the canonical JSON
of ``arrays`` and ``meta`` together, and each array's bytes must match its own ``sha256``, so a
flipped byte anywhere -- also in formats without checksums of their own (XML, HDF5) -- is
reported instead of resuming from wrong data. Arrays are plain numbers only (dtype kinds
``b``, ``i``, ``u``, ``f``); ``.npy`` members are parsed without pickle and nothing read is
unpickled (the engines a checkpoint holds are another matter: see :mod:`granum.io.checkpoint`).

Sizes are checked before data are read or inflated: zip members (stored uncompressed, as granum
writes them) and HDF5 datasets (uncompressed) against the array table of the manifest (shape x
item size, plus the ``.npy`` header), both as declared and as actually read; a ``.gz``/``.bz2``
layer is inflated as a stream, at most to the size the inner zip's manifest implies and never
beyond a fixed allowance or ratio (see :data:`_INFLATE_RATIO`), so a decompression bomb is
refused instead of filling memory or the temporary folder. A file that is not a granum checkpoint -- a YADE checkpoint
(boost::serialization, binary or XML), another zip, XML or HDF5 file, a picture, text -- is
reported as such by :class:`CheckpointError`, as are truncated and corrupt files.
"""

from __future__ import annotations

import base64
import bz2
import gzip
import hashlib
import io
import json
import re
import shutil
import tempfile
import zipfile
import zlib
from xml.etree import ElementTree as ET

import numpy as np

FORMAT_TAG = "granum-checkpoint"
FORMAT_VERSION = 1

#: Inner formats by file extension; any other name is written as ``yade``.
FORMAT_EXTENSIONS = {".yade": "yade", ".xml": "xml", ".h5": "h5", ".hdf5": "h5"}
#: Compressions by trailing extension.
COMPRESSIONS = {".gz": "gz", ".bz2": "bz2"}

_MAGIC_ZIP = b"PK\x03\x04"
_MAGIC_HDF5 = b"\x89HDF\r\n\x1a\n"
_MAGIC_GZIP = b"\x1f\x8b"
_MAGIC_BZ2 = b"BZh"
_YADE_BINARY = b"serialization::archive"   # boost's binary archive signature, at byte 8 of YADE's .yade files
_ZIP_MANIFEST = "granum.json"
_ZIP_DATE = (1980, 1, 1, 0, 0, 0)
_H5_ATTR = "granum-checkpoint"
_DTYPE = re.compile(r"[<>|=]?(b1|[iu][1248]|f[48])")
# characters XML 1.0 cannot carry (and CR, which parsers turn into LF): such strings are stored in base64
_XML_UNSAFE = re.compile("[^\t\n\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")
#: Bytes an ``.npy`` member may hold beyond its array data (its header; NumPy writes 128 or so).
_NPY_SLACK = 4096
#: Largest manifest (``granum.json``) read [bytes]; a granum scene's manifest is a few kB to a few MB.
_MANIFEST_MAX = 16 << 20
#: Bytes a compressed (``.gz``/``.bz2``) checkpoint may inflate to without further justification, and the
#: ratio to its compressed size beyond that. A granum checkpoint is mostly floating-point state (which
#: gzip and bzip2 shrink less than 10-fold) plus spare capacity, at most as large again (tables grow by
#: doubling), so a real one inflates far less than 1000-fold; a decompression bomb (zeros: 1:10^6 with
#: bzip2) is stopped after the allowance instead of filling the disk.
_INFLATE_FLOOR = 32 << 20
_INFLATE_RATIO = 1000
#: Per-member bytes a zip archive adds around its data (local header, central directory entry, zip64
#: extra fields), name excluded; the bound on an inflated ``.yade`` zip also allows for its end records.
_ZIP_MEMBER_OVERHEAD = 256
_ERRORS = (OSError, EOFError, ValueError, KeyError, TypeError, zipfile.BadZipFile, ET.ParseError, zlib.error)


class CheckpointError(RuntimeError):
    """A checkpoint cannot be written or read: not a granum checkpoint, truncated, corrupt, other
    version, or a scene value a checkpoint cannot store. (A RuntimeError, as YADE's load errors.)"""


class CheckpointNotFoundError(FileNotFoundError, CheckpointError):
    """The checkpoint file does not exist."""


def format_of_path(path: str) -> tuple[str, str | None]:
    """``(format, compression)`` a checkpoint named ``path`` is written in: format ``yade``,
    ``xml`` or ``h5``, compression None, ``gz`` or ``bz2``."""
    name = path.lower()
    compression = next((c for ext, c in COMPRESSIONS.items() if name.endswith(ext)), None)
    if compression is not None:
        name = name[: name.rfind(".")]
    fmt = next((f for ext, f in FORMAT_EXTENSIONS.items() if name.endswith(ext)), "yade")
    return fmt, compression


# ---- header and integrity -------------------------------------------------------------------
def json_canonical(value) -> str:
    """The JSON text ``value`` is digested as (sorted keys, no spaces, no NaN)."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), allow_nan=False)


def array_digest(a: np.ndarray) -> str:
    """SHA-256 of the bytes of ``a`` in C order."""
    return hashlib.sha256(np.ascontiguousarray(a).reshape(-1).view(np.uint8)).hexdigest()


def header_digest(meta, table: dict) -> str:
    return hashlib.sha256(json_canonical({"meta": meta, "arrays": table}).encode()).hexdigest()


def header_make(meta, arrays: dict[str, np.ndarray]) -> dict:
    """The header stored with ``arrays``: format tag, version, digest, array table and ``meta``."""
    for name, a in arrays.items():
        if not _DTYPE.fullmatch(a.dtype.str):
            raise CheckpointError(f"array {name!r} has dtype {a.dtype}; checkpoints store numbers and booleans only")
    table = {name: {"dtype": a.dtype.str, "shape": list(a.shape), "sha256": array_digest(a)}
             for name, a in arrays.items()}
    return {"format": FORMAT_TAG, "version": FORMAT_VERSION, "digest": header_digest(meta, table),
            "arrays": table, "meta": meta}


def header_check(header, source: str) -> None:
    """Raise :class:`CheckpointError` unless ``header`` is an intact header of this format version."""
    if not isinstance(header, dict) or header.get("format") != FORMAT_TAG:
        raise CheckpointError(f"{source} is not a granum checkpoint (no {FORMAT_TAG!r} format tag)")
    version = header.get("version")
    if version != FORMAT_VERSION:
        raise CheckpointError(f"{source} is a granum checkpoint of format version {version!r}; this granum reads "
                              f"version {FORMAT_VERSION} only")
    table = header.get("arrays")
    if not isinstance(table, dict) or "meta" not in header:
        raise CheckpointError(f"{source}: corrupt checkpoint header (no array table or manifest)")
    if header_digest(header["meta"], table) != header.get("digest"):
        raise CheckpointError(f"{source}: corrupt checkpoint (the manifest does not match its checksum)")
    for name, spec in table.items():
        ok = (isinstance(spec, dict) and isinstance(spec.get("dtype"), str) and _DTYPE.fullmatch(spec["dtype"])
              and isinstance(spec.get("shape"), list) and all(isinstance(n, int) and n >= 0 for n in spec["shape"]))
        if not ok:
            raise CheckpointError(f"{source}: corrupt checkpoint (bad description of array {name!r})")


def _array_check(name: str, a: np.ndarray, spec: dict, source: str) -> np.ndarray:
    if a.dtype.str != spec["dtype"] or list(a.shape) != spec["shape"]:
        raise CheckpointError(f"{source}: corrupt checkpoint (array {name!r} is {a.dtype.str} {list(a.shape)}, "
                              f"the manifest says {spec['dtype']} {spec['shape']})")
    if array_digest(a) != spec["sha256"]:
        raise CheckpointError(f"{source}: corrupt checkpoint (the data of array {name!r} do not match their checksum)")
    return a.astype(a.dtype.newbyteorder("="), copy=False)


# ---- zip (.yade) -------------------------------------------------------------------------------
def _zip_write(f, header: dict, arrays: dict) -> None:
    with zipfile.ZipFile(f, "w", zipfile.ZIP_STORED) as z:
        z.writestr(zipfile.ZipInfo(_ZIP_MANIFEST, _ZIP_DATE), json_canonical(header))
        for name, a in arrays.items():
            with z.open(zipfile.ZipInfo(f"arrays/{name}.npy", _ZIP_DATE), "w", force_zip64=True) as member:
                np.lib.format.write_array(member, np.ascontiguousarray(a), allow_pickle=False)


def array_nbytes(spec: dict) -> int:
    """Bytes of the data of an array described by the header entry ``spec`` (shape x item size)."""
    return int(np.prod(spec["shape"], dtype=object)) * np.dtype(spec["dtype"]).itemsize


def _zip_member(z: zipfile.ZipFile, member: str, limit: int, source: str) -> bytes:
    """The bytes of ``member``, refused unless it is stored uncompressed, as granum writes it, and both its
    size in the central directory and the bytes actually read are at most ``limit``."""
    try:
        info = z.getinfo(member)
    except KeyError:
        raise CheckpointError(f"{source}: corrupt checkpoint (no member {member})") from None
    if info.compress_type != zipfile.ZIP_STORED:
        raise CheckpointError(f"{source}: member {member} is compressed (method {info.compress_type}); granum "
                              f"stores checkpoint members uncompressed (compress the whole file: .yade.gz)")
    if info.file_size > limit:
        raise CheckpointError(f"{source}: member {member} is {info.file_size} bytes; the manifest allows at "
                              f"most {limit}")
    with z.open(info) as m:
        data = m.read(limit + 1)
    if len(data) > limit:
        raise CheckpointError(f"{source}: member {member} holds more than the {limit} bytes the manifest allows")
    return data


def _npy_parse(name: str, data: bytes, spec: dict, source: str) -> np.ndarray:
    """The array of an ``.npy`` member, its header checked against ``spec`` before any data are used."""
    buf = io.BytesIO(data)
    version = np.lib.format.read_magic(buf)
    read_header = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
    shape, fortran_order, dtype = read_header(buf)
    if dtype.str != spec["dtype"] or list(shape) != spec["shape"] or fortran_order:
        raise CheckpointError(f"{source}: corrupt checkpoint (array {name!r} is {dtype.str} {list(shape)}"
                              f"{' in Fortran order' if fortran_order else ''}, the manifest says {spec['dtype']} "
                              f"{spec['shape']})")
    raw = data[buf.tell():]
    if len(raw) != array_nbytes(spec):
        raise CheckpointError(f"{source}: corrupt checkpoint (array {name!r} has {len(raw)} bytes of data, "
                              f"the manifest says {array_nbytes(spec)})")
    return np.frombuffer(raw, dtype).reshape(shape).copy()


def _zip_read(f, source: str) -> tuple:
    with zipfile.ZipFile(f) as z:
        if _ZIP_MANIFEST not in z.namelist():
            raise CheckpointError(f"{source} is a zip archive but not a granum checkpoint (no {_ZIP_MANIFEST})")
        header = json.loads(_zip_member(z, _ZIP_MANIFEST, _MANIFEST_MAX, source))
        header_check(header, source)
        arrays = {}
        for name, spec in header["arrays"].items():
            data = _zip_member(z, f"arrays/{name}.npy", array_nbytes(spec) + _NPY_SLACK, source)
            arrays[name] = _array_check(name, _npy_parse(name, data, spec, source), spec, source)
    return header["meta"], arrays


# ---- HDF5 (.h5) ----------------------------------------------------------------------------------
def _h5_write(f, header: dict, arrays: dict) -> None:
    import h5py

    with h5py.File(f, "w") as h:
        h.attrs[_H5_ATTR] = json_canonical(header)
        for name, a in arrays.items():
            h.create_dataset(f"arrays/{name}", data=a)


def _h5_read(f, source: str) -> tuple:
    import h5py

    with h5py.File(f, "r") as h:
        if _H5_ATTR not in h.attrs:
            raise CheckpointError(f"{source} is an HDF5 file but not a granum checkpoint (no {_H5_ATTR!r} attribute)")
        header = json.loads(h.attrs[_H5_ATTR])
        header_check(header, source)
        arrays = {}
        for name, spec in header["arrays"].items():
            d = h.get(f"arrays/{name}")
            if not isinstance(d, h5py.Dataset):
                raise CheckpointError(f"{source}: corrupt checkpoint (no dataset arrays/{name})")
            if d.dtype.str != spec["dtype"] or list(d.shape) != spec["shape"]:
                raise CheckpointError(f"{source}: corrupt checkpoint (array {name!r} is {d.dtype.str} "
                                      f"{list(d.shape)}, the manifest says {spec['dtype']} {spec['shape']})")
            # granum writes datasets uncompressed and whole: stored bytes = data bytes, nothing to inflate
            if d.compression is not None or d.id.get_storage_size() != array_nbytes(spec):
                raise CheckpointError(f"{source}: array {name!r} is stored in {d.id.get_storage_size()} bytes "
                                      f"(compression {d.compression}); granum stores its {array_nbytes(spec)} "
                                      f"bytes uncompressed")
            arrays[name] = _array_check(name, d[()], spec, source)
    return header["meta"], arrays


# ---- XML (.xml) ----------------------------------------------------------------------------------
def _xml_text(el: ET.Element, text: str, attr: str = "") -> None:
    """Put ``text`` into ``el`` (as attribute ``attr`` if given), in base64 where XML cannot carry it."""
    coded = _XML_UNSAFE.search(text) is not None
    if coded:
        text = base64.b64encode(text.encode("utf-8")).decode("ascii")
    if attr:
        el.set(attr + "64" if coded else attr, text)
        return
    el.text = text
    if coded:
        el.set("encoding", "base64")


def xml_from_tree(value, key: str | None = None) -> ET.Element:
    """The element of a JSON value (see the module docstring); ``key``: its name in the enclosing object."""
    if value is None:
        el = ET.Element("null")
    elif isinstance(value, bool):
        el = ET.Element("bool")
        el.text = "true" if value else "false"
    elif isinstance(value, int):
        el = ET.Element("int")
        el.text = str(value)
    elif isinstance(value, float):
        el = ET.Element("float")
        el.text = repr(value)
    elif isinstance(value, str):
        el = ET.Element("str")
        _xml_text(el, value)
    elif isinstance(value, list):
        el = ET.Element("list")
        el.extend(xml_from_tree(v) for v in value)
    elif isinstance(value, dict):
        el = ET.Element("object")
        el.extend(xml_from_tree(v, k) for k, v in value.items())
    else:
        raise TypeError(f"not a JSON value: {value!r}")
    if key is not None:
        _xml_text(el, key, "key")
    return el


def _xml_str(el: ET.Element, attr: str = "") -> str:
    if attr:
        coded = el.get(attr + "64")
        return base64.b64decode(coded).decode("utf-8") if coded is not None else el.attrib[attr]
    text = el.text or ""
    return base64.b64decode(text).decode("utf-8") if el.get("encoding") == "base64" else text


def xml_to_tree(el: ET.Element):
    """The JSON value of an element written by :func:`xml_from_tree`."""
    tag = el.tag
    if tag == "null":
        return None
    if tag == "bool":
        return {"true": True, "false": False}[el.text]
    if tag == "int":
        return int(el.text)
    if tag == "float":
        return float(el.text)
    if tag == "str":
        return _xml_str(el)
    if tag == "list":
        return [xml_to_tree(c) for c in el]
    if tag == "object":
        return {_xml_str(c, "key"): xml_to_tree(c) for c in el}
    raise ValueError(f"unexpected element <{tag}> in the manifest")


def _xml_write(f, header: dict, arrays: dict) -> None:
    # imported here: xml.sax.saxutils imports urllib.request, http.client and ssl, about 10 ms of every start
    from xml.sax.saxutils import quoteattr

    f.write(b'<?xml version="1.0" encoding="utf-8"?>\n')
    f.write(f'<{FORMAT_TAG} format="{FORMAT_TAG}" version="{FORMAT_VERSION}" digest="{header["digest"]}">\n'
            .encode())
    meta = ET.Element("meta")
    meta.append(xml_from_tree(header["meta"]))
    ET.indent(meta, level=1)
    f.write(b"  " + ET.tostring(meta, encoding="utf-8", xml_declaration=False) + b"\n  <arrays>\n")
    for name, a in arrays.items():
        spec = header["arrays"][name]
        f.write(f'    <array name={quoteattr(name)} dtype={quoteattr(spec["dtype"])} '
                f'shape="{" ".join(map(str, spec["shape"]))}" sha256="{spec["sha256"]}">'.encode())
        f.write(base64.b64encode(np.ascontiguousarray(a).reshape(-1).view(np.uint8)))
        f.write(b"</array>\n")
    f.write(f"  </arrays>\n</{FORMAT_TAG}>\n".encode())


def _xml_read(f, source: str) -> tuple:
    root = ET.parse(f).getroot()
    if root.tag != FORMAT_TAG:
        raise CheckpointError(f"{source} is an XML document but not a granum checkpoint (root element <{root.tag}>)")
    meta_el, arrays_el = root.find("meta"), root.find("arrays")
    if meta_el is None or arrays_el is None or len(meta_el) != 1:
        raise CheckpointError(f"{source}: corrupt checkpoint (no <meta> or <arrays> element)")
    table, data = {}, {}
    for el in arrays_el:
        name = el.attrib["name"]
        table[name] = {"dtype": el.attrib["dtype"], "shape": [int(n) for n in el.attrib["shape"].split()],
                       "sha256": el.attrib["sha256"]}
        data[name] = el.text or ""
    version = root.get("version")
    header = {"format": root.get("format"), "version": int(version) if version and version.isdigit() else version,
              "digest": root.get("digest"), "arrays": table, "meta": xml_to_tree(meta_el[0])}
    header_check(header, source)
    arrays = {}
    for name, spec in table.items():
        raw = base64.b64decode(data[name], validate=True)
        dtype = np.dtype(spec["dtype"])
        if len(raw) != dtype.itemsize * int(np.prod(spec["shape"])):
            raise CheckpointError(f"{source}: corrupt checkpoint (array {name!r} has {len(raw)} bytes)")
        arrays[name] = _array_check(name, np.frombuffer(raw, dtype).reshape(spec["shape"]).copy(), spec, source)
    return header["meta"], arrays


_WRITERS = {"yade": _zip_write, "xml": _xml_write, "h5": _h5_write}
_COMPRESSORS = {"gz": lambda f: gzip.GzipFile(filename="", mode="wb", fileobj=f, mtime=0),
                "bz2": lambda f: bz2.BZ2File(f, "wb")}


def container_write(f, fmt: str, compression: str | None, meta, arrays: dict[str, np.ndarray]) -> None:
    """Write ``meta`` (JSON values) and ``arrays`` to the seekable binary file ``f`` in format ``fmt``
    (``yade``, ``xml``, ``h5``), compressed with ``compression`` (None, ``gz``, ``bz2``)."""
    header = header_make(meta, arrays)
    if compression is None:
        _WRITERS[fmt](f, header, arrays)
        return
    with tempfile.TemporaryFile() as inner:
        _WRITERS[fmt](inner, header, arrays)
        inner.seek(0)
        with _COMPRESSORS[compression](f) as z:
            shutil.copyfileobj(inner, z)


def _describe(head: bytes) -> str:
    """What a file starting with ``head`` is, for errors about files that are not granum checkpoints."""
    if _YADE_BINARY in head[:64]:
        return "a YADE checkpoint (boost::serialization binary archive), which granum cannot read"
    if b"boost_serialization" in head:
        return "a YADE checkpoint (boost::serialization XML archive), which granum cannot read"
    if not head:
        return "an empty file, not a granum checkpoint"
    return f"not a granum checkpoint (unrecognised content starting with {head[:16]!r})"


def _inner_read(f, source: str) -> tuple:
    head = f.read(1024)
    f.seek(0)
    if head.startswith(_MAGIC_ZIP):
        return _zip_read(f, source)
    if head.startswith(_MAGIC_HDF5):
        return _h5_read(f, source)
    if head.lstrip(b"\xef\xbb\xbf \t\r\n").startswith(b"<") and b"<!DOCTYPE" not in head and b"<!ENTITY" not in head:
        return _xml_read(f, source)
    raise CheckpointError(f"{source} is {_describe(head)}")


def _zip_bound(head: bytes) -> int | None:
    """Largest size a ``.yade`` zip starting with ``head`` may have, from the array table of its manifest
    (the first member, as granum writes it); None when ``head`` does not start with a readable manifest."""
    if len(head) < 30 or not head.startswith(_MAGIC_ZIP):
        return None
    method, size, name_len, extra_len = (int.from_bytes(head[k:k + n], "little")
                                         for k, n in ((8, 2), (18, 4), (26, 2), (28, 2)))
    start = 30 + name_len + extra_len
    if head[30:30 + name_len] != _ZIP_MANIFEST.encode() or method != zipfile.ZIP_STORED or \
            len(head) < start + size:
        return None
    try:
        table = json.loads(head[start:start + size])["arrays"]
        data = sum(array_nbytes(spec) + _NPY_SLACK + 2 * (len(name) + _ZIP_MEMBER_OVERHEAD)
                   for name, spec in table.items())
    except (ValueError, KeyError, TypeError, AttributeError):
        return None
    return start + size + 2 * _ZIP_MEMBER_OVERHEAD + data


def _inflate(z, out, compressed_size: int, source: str) -> None:
    """Copy the decompressed stream ``z`` to the file ``out``, refusing to go beyond what the checkpoint
    may legitimately hold: for a ``.yade`` zip, the size its manifest's array table implies; in any case
    :data:`_INFLATE_FLOOR` or :data:`_INFLATE_RATIO` times the ``compressed_size`` [bytes]."""
    limit = max(_INFLATE_FLOOR, _INFLATE_RATIO * compressed_size)
    head = z.read(min(limit, _MANIFEST_MAX + 64 * 1024))
    bound = _zip_bound(head)
    if bound is not None:
        limit = min(limit, bound)
    out.write(head)
    written = len(head)
    while chunk := z.read(1 << 20):
        written += len(chunk)
        if written > limit:
            raise CheckpointError(f"{source} inflates to more than {limit} bytes, more than a checkpoint of "
                                  f"its size{' and manifest' if bound is not None else ''} can hold "
                                  f"(a decompression bomb?); refused")
        out.write(chunk)


def container_read(f, source: str) -> tuple[object, dict[str, np.ndarray]]:
    """``(meta, arrays)`` of the checkpoint in the seekable binary file ``f`` (any format, detected from
    its content); ``source`` names it in errors. Raises :class:`CheckpointError`."""
    try:
        head = f.read(4)
        f.seek(0)
        compression = "gzip" if head.startswith(_MAGIC_GZIP) else "bzip2" if head.startswith(_MAGIC_BZ2) else None
        if compression is None:
            return _inner_read(f, source)
        compressed_size = f.seek(0, io.SEEK_END)
        f.seek(0)
        with tempfile.TemporaryFile() as inner:
            with gzip.GzipFile(fileobj=f) if compression == "gzip" else bz2.BZ2File(f) as z:
                _inflate(z, inner, compressed_size, f"{source} ({compression}-compressed)")
            inner.seek(0)
            return _inner_read(inner, f"{source} ({compression}-compressed)")
    except CheckpointError:
        raise
    except _ERRORS as e:
        raise CheckpointError(f"{source} is truncated or corrupt: {type(e).__name__}: {e}") from e
