#!/usr/bin/env python3
"""Writes the synthetic DXF fixtures in this folder (original work, MIT). Run from here."""
import math


def g(code, value):
    return f"{code:>3}\n{value}\n"


def polyline(layer, pts, closed=False, bulges=None):
    s = g(0, "POLYLINE") + g(8, layer) + g(66, 1) + g(70, 1 if closed else 0)
    for i, (x, y) in enumerate(pts):
        s += g(0, "VERTEX") + g(8, layer) + g(10, f"{x:.4f}") + g(20, f"{y:.4f}")
        if bulges and bulges[i]:
            s += g(42, f"{bulges[i]:.6f}")
    return s + g(0, "SEQEND") + g(8, layer)


def text(layer, x, y, t):
    return g(0, "TEXT") + g(8, layer) + g(10, x) + g(20, y) + g(40, 2.5) + g(1, t)


def point(layer, x, y):
    return g(0, "POINT") + g(8, layer) + g(10, f"{x:.4f}") + g(20, f"{y:.4f}")


def line(layer, a, b):
    return g(0, "LINE") + g(8, layer) + g(10, a[0]) + g(20, a[1]) + g(11, b[0]) + g(21, b[1])


def aama():
    blocks, inserts = "", ""
    for size, k in (("S", 0.9), ("M", 1.0), ("L", 1.1)):
        sc = lambda pts: [(x * k, y * k) for x, y in pts]
        # FRONT: 200 x 300 mm with a bulged (arc) top, boundary split in three open
        # polylines, the last one drawn backwards.
        b = g(0, "BLOCK") + g(8, 0) + g(2, f"FRONT_{size}") + g(70, 64) + g(10, 0) + g(20, 0)
        b += text(1, 50, 150, "Piece Name: FRONT") + text(1, 50, 140, f"Size: {size}")
        b += polyline(1, sc([(0, 0), (200, 0), (200, 300)]))
        b += polyline(1, sc([(200, 300), (0, 300)]), bulges=[0.5, 0])
        b += polyline(1, sc([(0, 0), (0, 300)]))
        if size == "M":
            for p in [(0, 0), (200, 0), (200, 300), (0, 300)]:
                b += point(2, *p)
            b += point(4, 100, 0) + point(4, 200, 150)
        b += line(7, (100 * k, 50 * k), (100 * k, 250 * k))
        b += polyline(8, sc([(20, 100), (180, 100)]))
        b += g(0, "ENDBLK") + g(8, 0)
        # BACK: closed trapezoid.
        b += g(0, "BLOCK") + g(8, 0) + g(2, f"BACK_{size}") + g(70, 64) + g(10, 0) + g(20, 0)
        b += text(1, 50, 150, "Piece Name: BACK") + text(1, 50, 140, f"Size: {size}")
        b += polyline(1, sc([(0, 0), (40, 280), (180, 280), (220, 0)]), closed=True)
        # An internal cutout (layer 11): a 20 mm square hole.
        b += polyline(11, sc([(100, 100), (120, 100), (120, 120), (100, 120)]), closed=True)
        b += line(7, (110 * k, 50 * k), (110 * k, 250 * k))
        b += g(0, "ENDBLK") + g(8, 0)
        blocks += b
        for name in ("FRONT", "BACK"):
            inserts += g(0, "INSERT") + g(8, 1) + g(2, f"{name}_{size}") + g(10, 0) + g(20, 0)
    ents = inserts + text(1, 0, 0, "Style Name: SYNTHETIC") + text(1, 0, 0, "Sample Size: M")
    ents += text(1, 0, 0, "Units: METRIC")
    out = g(0, "SECTION") + g(2, "HEADER") + g(0, "ENDSEC")
    out += g(0, "SECTION") + g(2, "BLOCKS") + blocks + g(0, "ENDSEC")
    out += g(0, "SECTION") + g(2, "ENTITIES") + ents + g(0, "ENDSEC") + g(0, "EOF")
    open("synthetic_aama.dxf", "w", newline="\r\n").write(out)


def plain():
    e = ""
    # A 50 x 50 cm square (LWPOLYLINE) with a circular hole of radius 5 cm.
    e += g(0, "LWPOLYLINE") + g(8, "PANEL") + g(90, 4) + g(70, 1)
    for x, y in [(0, 0), (50, 0), (50, 50), (0, 50)]:
        e += g(10, x) + g(20, y)
    e += g(0, "CIRCLE") + g(8, "PANEL") + g(10, 25) + g(20, 25) + g(40, 5)
    # An open cubic spline inside the square: an internal line.
    e += g(0, "SPLINE") + g(8, "MARKS") + g(70, 8) + g(71, 3) + g(72, 8) + g(73, 4)
    for k in (0, 0, 0, 0, 1, 1, 1, 1):
        e += g(40, k)
    for x, y in [(5, 40), (15, 45), (35, 35), (45, 40)]:
        e += g(10, x) + g(20, y)
    # A "D": a LINE and an ARC meeting end to end, named by the TEXT inside it.
    e += line("0", (100, 40), (100, 0))
    e += g(0, "ARC") + g(8, "0") + g(10, 100) + g(20, 20) + g(40, 20) + g(50, 270) + g(51, 90)
    e += text("0", 105, 20, "POCKET")
    hdr = g(9, "$ACADVER") + g(1, "AC1015") + g(9, "$INSUNITS") + g(70, 5)
    out = g(0, "SECTION") + g(2, "HEADER") + hdr + g(0, "ENDSEC")
    out += g(0, "SECTION") + g(2, "ENTITIES") + e + g(0, "ENDSEC") + g(0, "EOF")
    open("synthetic_plain.dxf", "w", newline="\n").write(out)


def attrib():
    """Piece name and size in ATTRIBs following the INSERT instead of TEXT in the block."""
    b = g(0, "BLOCK") + g(8, 0) + g(2, "B1") + g(70, 2) + g(10, 0) + g(20, 0)
    b += polyline(1, [(0, 0), (4, 0), (4, 2), (0, 2)], closed=True)
    b += g(0, "ENDBLK")
    e = g(0, "INSERT") + g(8, 1) + g(66, 1) + g(2, "B1") + g(10, 0) + g(20, 0)
    for tag, val in (("PIECE", "Piece Name: CUFF"), ("SIZE", "Size: 10")):
        e += g(0, "ATTRIB") + g(8, 1) + g(10, 0) + g(20, 0) + g(40, 0.2) + g(1, val) + g(2, tag) + g(70, 0)
    e += g(0, "SEQEND") + g(8, 1)
    e += text(1, 0, 0, "Units: ENGLISH")
    out = g(0, "SECTION") + g(2, "BLOCKS") + b + g(0, "ENDSEC")
    out += g(0, "SECTION") + g(2, "ENTITIES") + e + g(0, "ENDSEC") + g(0, "EOF")
    open("synthetic_attrib.dxf", "w", newline="\n").write(out)


def fold():
    """A piece cut on the fold: its right half drawn (fold on x = 0), with a mirror line (layer
    6) along the fold, a notch, a turn point, a grain line and an internal line."""
    half = [(0, 0), (150, 0), (160, 300), (40, 320), (0, 300)]
    b = g(0, "BLOCK") + g(8, 0) + g(2, "YOKE_M") + g(70, 64) + g(10, 0) + g(20, 0)
    b += text(1, 50, 150, "Piece Name: YOKE") + text(1, 50, 140, "Size: M")
    b += polyline(1, half, closed=True)
    b += point(4, 150, 0) + point(2, 160, 300)
    b += line(6, (0, 0), (0, 300))
    b += line(7, (80, 50), (80, 250))
    b += polyline(8, [(30, 100), (120, 100)])
    b += g(0, "ENDBLK") + g(8, 0)
    ents = g(0, "INSERT") + g(8, 1) + g(2, "YOKE_M") + g(10, 0) + g(20, 0)
    ents += text(1, 0, 0, "Sample Size: M") + text(1, 0, 0, "Units: METRIC")
    out = g(0, "SECTION") + g(2, "HEADER") + g(0, "ENDSEC")
    out += g(0, "SECTION") + g(2, "BLOCKS") + b + g(0, "ENDSEC")
    out += g(0, "SECTION") + g(2, "ENTITIES") + ents + g(0, "ENDSEC") + g(0, "EOF")
    open("synthetic_fold.dxf", "w", newline="\r\n").write(out)


def cut():
    """Cut quantities in a two-size nest (M, L): SLEEVE cut twice (an asymmetric trapezoid with a
    notch on its left edge), PANEL once, ALT cut 0 times; AccuMark's way, `Quantity:` only in
    the sample size's (M) blocks."""
    shapes = {
        "SLEEVE": [(0, 0), (200, 0), (160, 250), (20, 220)],
        "PANEL": [(0, 0), (100, 0), (100, 100), (0, 100)],
        "ALT": [(0, 0), (80, 0), (40, 90)],
    }
    quantity = {"SLEEVE": 2, "PANEL": 1, "ALT": 0}
    b, ents = "", ""
    for size, k in (("M", 1.0), ("L", 1.1)):
        for name, pts in shapes.items():
            block = f"{name}_{size}"
            b += g(0, "BLOCK") + g(8, 0) + g(2, block) + g(70, 64) + g(10, 0) + g(20, 0)
            b += text(1, 10, 10, f"Piece Name: {name}") + text(1, 10, 5, f"Size: {size}")
            if size == "M":
                b += text(1, 10, 0, f"Quantity: {quantity[name]}")
            b += polyline(1, [(x * k, y * k) for x, y in pts], closed=True)
            if name == "SLEEVE":
                b += point(4, 10 * k, 110 * k)
            b += line(7, (100 * k, 20 * k), (100 * k, 200 * k)) if name == "SLEEVE" else ""
            b += g(0, "ENDBLK") + g(8, 0)
            ents += g(0, "INSERT") + g(8, 1) + g(2, block) + g(10, 0) + g(20, 0)
    ents += text(1, 0, 0, "Sample Size: M") + text(1, 0, 0, "Units: METRIC")
    out = g(0, "SECTION") + g(2, "HEADER") + g(0, "ENDSEC")
    out += g(0, "SECTION") + g(2, "BLOCKS") + b + g(0, "ENDSEC")
    out += g(0, "SECTION") + g(2, "ENTITIES") + ents + g(0, "ENDSEC") + g(0, "EOF")
    open("synthetic_cut.dxf", "w", newline="\r\n").write(out)


aama()
plain()
attrib()
fold()
cut()
print("front M perimeter mm:", 200 + 300 + 300 + 125 * 4 * math.atan(0.5))
