"""Content-only bytes of a ``.3dm`` archive written by rhino3dm (``--format 3dm``).

openNURBS stamps an archive with the clock: its properties table records when the model was
created and last edited (``TCODE_PROPERTIES_REVISIONHISTORY``), and an archive written to a
file also records the file's full path (``TCODE_PROPERTIES_AS_FILE_NAME``). dgpc writes the
model to memory (``File3dm.Encode``: no path recorded), then sets both times to
:data:`FIXED_TIME` here, so that the bytes depend on the model alone.

The archive is a header of 32 bytes and a sequence of chunks: a 4-byte type code, then (for
archive versions 5 and later) an 8-byte length and that many bytes of content, or, when the
type code has the short bit, an 8-byte value and no content. The revision history chunk
lies in the properties table (``TCODE_PROPERTIES_TABLE``); its content is a version byte,
the creator's name, the creation time, the last editor's name, the last-edit time and the
revision count, followed by its CRC-32 (zlib's). Each time is 8 little-endian int32 of a C
``struct tm`` (seconds, minutes, hours, day of month, month 0-11, years since 1900, day of
week, day of year). Anything other than that layout (a CRC that does not match, a name that
does not fit) is an error: the bytes are never patched on a guess.
"""

from __future__ import annotations

import struct
import zlib

from ..errors import DgpcError

#: 2000-01-01 00:00:00, a Saturday, day 0 of the year, as openNURBS's ``struct tm`` fields.
FIXED_TIME = (0, 0, 0, 1, 0, 100, 6, 0)
HEADER = 32
TCODE_SHORT = 0x80000000
TCODE_PROPERTIES_TABLE = 0x10000014
TCODE_PROPERTIES_REVISIONHISTORY = 0x20008021
TCODE_ENDOFTABLE = 0xFFFFFFFF


def _chunks(blob: bytes, start: int, stop: int):
    """``(type code, content start, content length)`` of each chunk in ``blob[start:stop]``
    (length 0 for a short chunk)."""
    pos = start
    while pos + 12 <= stop:
        tcode, length = struct.unpack_from("<Iq", blob, pos)
        if tcode & TCODE_SHORT:
            yield tcode, pos + 12, 0
            pos += 12
            continue
        if length < 0 or pos + 12 + length > stop:
            raise ValueError(f"chunk {tcode:#x} at byte {pos} runs past its table")
        yield tcode, pos + 12, length
        pos += 12 + length


def _string_end(blob: bytes, pos: int) -> int:
    """The end of an openNURBS wide string at ``pos``: an int32 count of UTF-16 units (the
    terminating zero included), then the units."""
    (count,) = struct.unpack_from("<i", blob, pos)
    if count < 0:
        raise ValueError("negative string length")
    return pos + 4 + 2 * count


def fixed_times(blob: bytes) -> bytes:
    """``blob`` (a 3dm archive, version 5 or later) with the creation and last-edit times of
    its revision history set to :data:`FIXED_TIME` and the chunk's CRC recomputed; the same
    length. DgpcError when the archive is not laid out as the module describes."""
    try:
        return _fixed_times(blob)
    except (ValueError, struct.error) as e:
        raise DgpcError(f"rhino3dm wrote a 3dm archive dgpc cannot make deterministic ({e})",
                        source="--format 3dm") from None


def _fixed_times(blob: bytes) -> bytes:
    if not blob.startswith(b"3D Geometry File Format "):
        raise ValueError("no 3dm header")
    out = bytearray(blob)
    for tcode, start, length in _chunks(blob, HEADER, len(blob)):
        if tcode != TCODE_PROPERTIES_TABLE:
            continue
        for sub, s_start, s_length in _chunks(blob, start, start + length):
            if sub == TCODE_ENDOFTABLE:
                break
            if sub != TCODE_PROPERTIES_REVISIONHISTORY:
                continue
            content = blob[s_start:s_start + s_length]
            if s_length < 4 or zlib.crc32(content[:-4]) != \
                    struct.unpack("<I", content[-4:])[0]:
                raise ValueError("the revision history's CRC does not match")
            created = _string_end(blob, s_start + 1)          # after the version byte
            edited = _string_end(blob, created + 32)
            if edited + 32 + 4 + 4 != s_start + s_length:
                raise ValueError("the revision history is not laid out as expected")
            fixed = struct.pack("<8i", *FIXED_TIME)
            out[created:created + 32] = fixed
            out[edited:edited + 32] = fixed
            body = bytes(out[s_start:s_start + s_length - 4])
            out[s_start + s_length - 4:s_start + s_length] = struct.pack("<I", zlib.crc32(body))
            return bytes(out)
        break
    raise ValueError("no revision history in its properties table")
