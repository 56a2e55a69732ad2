# Cem Yuksel's binary HAIR format (.hair), read and written with numpy: no bpy here, so the
# module can be used (and tested) outside Blender.
#
# Specification: http://www.cemyuksel.com/research/hairmodels/ and ringlet's
# include/ringlet/hair_file.h / docs/file-formats.md. A 128-byte little-endian header
#   0-3 "HAIR", 4-7 uint32 strands, 8-11 uint32 points, 12-15 uint32 array bits (1 segments,
#   2 points, 4 thickness, 8 transparency, 16 colour; bits 5-31 reserved = 0), 16-19 uint32
#   default segments, 20-23 float default thickness, 24-27 float default transparency,
#   28-39 float[3] default colour, 40-127 char[88] info
# followed by the arrays present in that order: segments (uint16 per strand = points - 1),
# points (3 float32 per point), thickness (float32 per point, the fibre DIAMETER), transparency
# (float32 per point), colour (3 float32 per point).
#
# The format has no unit. ringlet states its unit in the info text ("... 100 units per metre
# ..."); UnitsPerMetreFromInfo reads it back.
import re
import struct

import numpy as np

HEADER_SIZE = 128
SEGMENTS_BIT = 1
POINTS_BIT = 2
THICKNESS_BIT = 4
TRANSPARENCY_BIT = 8
COLORS_BIT = 16
KNOWN_BITS = 31
MAX_POINTS_PER_STRAND = 65536  # a segment count is a uint16
INFO_SIZE = 88


class HairFileError(ValueError):
    """A .hair file that cannot be read or written: one line naming the field."""


class HairData:
    """Strands stored flat, as in the file (file units, not converted).

    point_counts: uint32 array (strands,), each >= 2.
    points: float32 array (points, 3), root to tip per strand.
    thickness: float32 array (points,), fibre diameter, or None.
    colors: float32 array (points, 3) linear RGB, or None.
    transparency: float32 array (points,), or None.
    default_thickness, default_color: header defaults.
    info: the header's information text (str).
    """

    def __init__(self, point_counts, points, thickness=None, colors=None, transparency=None,
                 default_thickness=0.0, default_color=(1.0, 1.0, 1.0), info=""):
        self.point_counts = np.asarray(point_counts, dtype=np.uint32)
        self.points = np.asarray(points, dtype=np.float32).reshape(-1, 3)
        self.thickness = None if thickness is None else np.asarray(thickness, dtype=np.float32)
        self.colors = None if colors is None else np.asarray(colors, dtype=np.float32).reshape(-1, 3)
        self.transparency = (None if transparency is None
                             else np.asarray(transparency, dtype=np.float32))
        self.default_thickness = float(default_thickness)
        self.default_color = tuple(float(c) for c in default_color)
        self.info = info

    @property
    def num_strands(self):
        return int(self.point_counts.size)

    @property
    def num_points(self):
        return int(self.points.shape[0])

    def widths(self):
        """Per-point diameters: the thickness array, or the header default everywhere."""
        if self.thickness is not None:
            return self.thickness
        return np.full(self.num_points, self.default_thickness, dtype=np.float32)


def units_per_metre_from_info(info):
    """The unit ringlet states in the info text ("... 100 units per metre ..."), or None."""
    match = re.search(r"([0-9][0-9.eE+-]*) units? per metre", info)
    if not match:
        return None
    try:
        value = float(match.group(1))
    except ValueError:
        return None
    return value if np.isfinite(value) and value > 0.0 else None


def decode(data):
    """Parses the bytes of a .hair file into HairData. Every count is checked against the
    file's size before anything is allocated; raises HairFileError with one line naming the
    field on any inconsistency."""
    size = len(data)
    if size < HEADER_SIZE:
        raise HairFileError("header: truncated, expected 128 bytes, got %d" % size)
    if data[0:4] != b"HAIR":
        raise HairFileError('header.signature: expected "HAIR" in bytes 0-3')
    strands, points, arrays, default_segments = struct.unpack_from("<4I", data, 4)
    default_thickness, default_transparency = struct.unpack_from("<2f", data, 20)
    default_color = struct.unpack_from("<3f", data, 28)
    info = bytes(data[40:128]).split(b"\0", 1)[0].decode("ascii", "replace")
    if arrays & ~KNOWN_BITS:
        raise HairFileError("header.arrays: reserved bits 5-31 must be 0, got 0x%08x" % arrays)
    if not arrays & POINTS_BIT:
        raise HairFileError("header.arrays: the points array (bit 1) is missing")
    with_segments = bool(arrays & SEGMENTS_BIT)
    with_thickness = bool(arrays & THICKNESS_BIT)
    with_transparency = bool(arrays & TRANSPARENCY_BIT)
    with_colors = bool(arrays & COLORS_BIT)
    expected = (HEADER_SIZE + (2 * strands if with_segments else 0) + 12 * points +
                (4 * points if with_thickness else 0) +
                (4 * points if with_transparency else 0) + (12 * points if with_colors else 0))
    if size < expected:
        raise HairFileError("arrays: truncated, header announces %d strands and %d points "
                            "needing %d bytes, got %d" % (strands, points, expected, size))
    if size > expected:
        raise HairFileError("arrays: %d unexpected bytes after the arrays announced by the "
                            "header (%d bytes)" % (size - expected, expected))
    if strands > points // 2:
        raise HairFileError("header.strand_count: %d strands need at least %d points (2 per "
                            "strand), but the header announces %d points"
                            % (strands, 2 * strands, points))
    offset = HEADER_SIZE
    if with_segments:
        segments = np.frombuffer(data, dtype="<u2", count=strands, offset=offset)
        offset += 2 * strands
        if strands and segments.min() == 0:
            k = int(np.argmin(segments))
            raise HairFileError("segments[%d]: expected at least 1 segment per strand, got 0" % k)
        point_counts = segments.astype(np.uint32) + 1
    else:
        if strands and (default_segments == 0 or default_segments == 0xFFFFFFFF):
            raise HairFileError("header.default_segments: expected at least 1 segment per "
                                "strand (no segments array), got %d" % default_segments)
        point_counts = np.full(strands, default_segments + 1, dtype=np.uint32)
    total = int(point_counts.sum(dtype=np.uint64))
    if total != points:
        raise HairFileError("header.point_count: %d points, but the segment counts add up to "
                            "%d points" % (points, total))
    positions = np.frombuffer(data, dtype="<f4", count=3 * points, offset=offset)
    offset += 12 * points
    positions = positions.reshape(points, 3).astype(np.float32)  # native order, own memory
    finite = np.isfinite(positions).all(axis=1)
    if not finite.all():
        raise HairFileError("points[%d]: expected finite coordinates" % int(np.argmin(finite)))
    thickness = None
    if with_thickness:
        thickness = np.frombuffer(data, dtype="<f4", count=points, offset=offset).astype(np.float32)
        offset += 4 * points
        good = np.isfinite(thickness) & (thickness >= 0.0)
        if not good.all():
            raise HairFileError("thickness[%d]: expected a finite thickness >= 0"
                                % int(np.argmin(good)))
    elif not (np.isfinite(default_thickness) and default_thickness >= 0.0):
        raise HairFileError("header.default_thickness: expected a finite thickness >= 0 (no "
                            "thickness array)")
    transparency = None
    if with_transparency:
        transparency = np.frombuffer(data, dtype="<f4", count=points,
                                     offset=offset).astype(np.float32)
        offset += 4 * points
    colors = None
    if with_colors:
        colors = np.frombuffer(data, dtype="<f4", count=3 * points,
                               offset=offset).reshape(points, 3).astype(np.float32)
        offset += 12 * points
        finite = np.isfinite(colors).all(axis=1)
        if not finite.all():
            raise HairFileError("colors[%d]: expected a finite RGB colour"
                                % int(np.argmin(finite)))
    return HairData(point_counts, positions, thickness, colors, transparency,
                    default_thickness, default_color, info)


def read(path):
    """Reads and decodes the .hair file at path; errors start with the path."""
    with open(path, "rb") as f:
        data = f.read()
    try:
        return decode(data)
    except HairFileError as e:
        raise HairFileError("%s: %s" % (path, e)) from None


def encode(hair):
    """The bytes of a .hair file for HairData (values written as given, float32). The segments
    array is left out when every strand has the same number of points, as ringlet does."""
    counts = np.asarray(hair.point_counts, dtype=np.int64)
    points = np.ascontiguousarray(hair.points, dtype="<f4").reshape(-1, 3)
    strands = counts.size
    if strands and counts.min() < 2:
        k = int(np.argmin(counts))
        raise HairFileError("point_counts[%d]: expected at least 2 points per strand, got %d"
                            % (k, counts[k]))
    if strands and counts.max() > MAX_POINTS_PER_STRAND:
        k = int(np.argmax(counts))
        raise HairFileError("point_counts[%d]: %d points; a .hair strand has at most 65535 "
                            "segments (65536 points)" % (k, counts[k]))
    if int(counts.sum()) != points.shape[0]:
        raise HairFileError("points: expected %d points (the sum of point_counts), got %d"
                            % (int(counts.sum()), points.shape[0]))
    if strands > 0xFFFFFFFF or points.shape[0] > 0xFFFFFFFF:
        raise HairFileError("more than 2^32-1 strands or points do not fit a .hair header")
    if not np.isfinite(points).all():
        raise HairFileError("points: expected finite coordinates")
    thickness = None
    if hair.thickness is not None:
        thickness = np.ascontiguousarray(hair.thickness, dtype="<f4").reshape(-1)
        if thickness.size != points.shape[0]:
            raise HairFileError("thickness: expected one per point (%d), got %d"
                                % (points.shape[0], thickness.size))
        if not (np.isfinite(thickness) & (thickness >= 0)).all():
            raise HairFileError("thickness: expected finite values >= 0")
    colors = None
    if hair.colors is not None:
        colors = np.ascontiguousarray(hair.colors, dtype="<f4").reshape(-1, 3)
        if colors.shape[0] != points.shape[0]:
            raise HairFileError("colors: expected one per point (%d), got %d"
                                % (points.shape[0], colors.shape[0]))
    info = hair.info.encode("ascii")
    if len(info) > INFO_SIZE - 1:
        raise HairFileError("info: expected at most 87 ASCII characters, got %d" % len(info))
    same = strands > 0 and bool((counts == counts[0]).all())
    with_segments = strands > 0 and not same
    arrays = ((SEGMENTS_BIT if with_segments else 0) | POINTS_BIT |
              (THICKNESS_BIT if thickness is not None else 0) |
              (COLORS_BIT if colors is not None else 0))
    mean_width = float(thickness.astype(np.float64).mean()) if thickness is not None and \
        thickness.size else hair.default_thickness
    mean_color = (tuple(colors.astype(np.float64).mean(axis=0)) if colors is not None and
                  colors.size else hair.default_color)
    header = bytearray(HEADER_SIZE)
    header[0:4] = b"HAIR"
    struct.pack_into("<4I", header, 4, strands, points.shape[0], arrays,
                     int(counts[0]) - 1 if same else 0)
    struct.pack_into("<2f", header, 20, mean_width, 0.0)
    struct.pack_into("<3f", header, 28, *mean_color)
    header[40:40 + len(info)] = info
    parts = [bytes(header)]
    if with_segments:
        parts.append((counts - 1).astype("<u2").tobytes())
    parts.append(points.tobytes())
    if thickness is not None:
        parts.append(thickness.tobytes())
    if colors is not None:
        parts.append(colors.tobytes())
    return b"".join(parts)


def _umask():
    """The process's file mode creation mask."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    import os
    mask = os.umask(0o022)  # not thread-safe, only where /proc is missing
    os.umask(mask)
    return mask


def write(path, hair):
    """Encodes hair and writes it atomically (a temporary file in the same folder, then a
    rename): the file appears only complete."""
    import os
    import tempfile
    data = encode(hair)
    folder = os.path.dirname(os.path.abspath(path))
    fd, temporary = tempfile.mkstemp(prefix=".ringlet-", suffix=".hair.tmp", dir=folder)
    try:
        # mkstemp makes the file private (0600); a saved file gets the mode any new file of the
        # user gets: 0666 less the umask (read without changing it: /proc's Umask line, Linux).
        os.fchmod(fd, 0o666 & ~_umask())
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise
