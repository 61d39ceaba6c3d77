#!/usr/bin/python3
"""The classic NetCDF writer the Exodus fixture scripts share (standard library only): for files
VTK's Exodus writer cannot write, byte by byte."""
import struct


class Cdf:
    """A tiny classic NetCDF writer (CDF-1, CDF-2 with 64-bit offsets, CDF-5 with 64-bit counts
    and offsets), laid out as the NetCDF classic format specification says: values
    `struct` kinds c b h i f d q; a variable whose first dimension has length 0 is a record
    variable of `numrecs` records (one record variable is stored unpadded)."""

    TYPES = {"c": 2, "b": 1, "h": 3, "i": 4, "f": 5, "d": 6, "q": 10}
    def __init__(self, version):
        self.version = version
        self.dims, self.vars, self.numrecs, self.global_attrs = [], [], 0, []
    def n(self, x):
        return struct.pack(">q" if self.version == 5 else ">i", x)
    def dim(self, name, n):
        names = [d[0] for d in self.dims]
        if name not in names:
            self.dims.append((name, n)); names.append(name)
        return names.index(name)
    def var(self, name, dims, kind, values, attrs=()):
        self.vars.append((name, [self.dim(*d) for d in dims], kind, values, list(attrs)))
    @staticmethod
    def pad(b):
        return b + b"\0" * (-len(b) % 4)
    def name(self, s):
        return self.n(len(s)) + self.pad(s.encode())
    def packed(self, kind, values):
        if kind == "c":
            return bytes(values)
        return struct.pack(">%d%s" % (len(values), kind), *values)
    def attrs(self, attrs):
        if not attrs:
            return b"\0" * 4 + self.n(0)
        out = struct.pack(">i", 12) + self.n(len(attrs))
        for n, kind, v in attrs:
            out += self.name(n) + struct.pack(">i", self.TYPES[kind]) + self.n(len(v))
            out += self.pad(self.packed(kind, v))
        return out
    def is_record(self, v):
        return bool(v[1]) and self.dims[v[1][0]][1] == 0
    def header(self, begins):
        out = b"CDF" + bytes([self.version]) + self.n(self.numrecs)
        out += struct.pack(">i", 10) + self.n(len(self.dims))
        for n, l in self.dims:
            out += self.name(n) + self.n(l)
        out += self.attrs(self.global_attrs)
        out += struct.pack(">i", 11) + self.n(len(self.vars))
        for v, b in zip(self.vars, begins):
            size = len(self.pad(self.packed(v[2], v[3])))
            if self.is_record(v):
                size //= max(self.numrecs, 1)
            out += self.name(v[0]) + self.n(len(v[1]))
            out += b"".join(self.n(d) for d in v[1])
            out += self.attrs(v[4]) + struct.pack(">i", self.TYPES[v[2]]) + self.n(size)
            out += struct.pack(">q" if self.version in (2, 5) else ">i", b)
        return out
    def bytes(self):
        at = len(self.header([0] * len(self.vars)))
        begins, fixed, records = [], b"", []
        for v in self.vars:
            if self.is_record(v):
                begins.append(None); records.append(v)
            else:
                begins.append(at + len(fixed)); fixed += self.pad(self.packed(v[2], v[3]))
        rec_at = at + len(fixed)
        slabs = [len(self.packed(v[2], v[3])) // max(self.numrecs, 1) for v in records]
        offset = 0
        for v, n in zip(records, slabs):
            begins[self.vars.index(v)] = rec_at + offset
            offset += n + (-n % 4) if len(records) > 1 else n
        data = b""
        for r in range(self.numrecs):
            for v, n in zip(records, slabs):
                chunk = self.packed(v[2], v[3])[r * n:(r + 1) * n]
                data += self.pad(chunk) if len(records) > 1 else chunk
        return self.header(begins) + fixed + data


def text(rows, w=33):
    """Rows of text as NUL-padded `char` values `w` wide (Exodus names)."""
    return [b for r in rows for b in r.encode().ljust(w, b"\0")]
