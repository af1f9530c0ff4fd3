"""Error measures of the liquid validation cases, shared by tetfsi's runs (scripts/report_metrics.py)
and OpenFOAM's (scripts/openfoam_peer.py), so that both codes are measured the same way.

Sloshing (first mode of a rectangular tank, length L, still depth H): the mode amplitude A(t), the
cos(k x) coefficient of a least-squares fit eta(x) = c + A cos(k x) of the surface elevation, k = pi / L.
Linear theory (Lamb 1932, "Hydrodynamics", sec. 227): eta = A0 cos(k x) cos(omega t) with
omega^2 = g k tanh(k H). `sloshing_frequency_and_decay` takes the frequency from the zero crossings of
A(t) (linear interpolation in time) and the amplitude change per period from its extrema (each refined
by a parabola through the three samples around it).

Dam break (Martin & Moyce 1952, "Part IV. An experimental study of the collapse of liquid columns on a
rigid horizontal plane", Phil. Trans. R. Soc. A 244, 312-324): a square column of side a collapses
along a floor. Their measured surge front Z = z / a against T = t sqrt(2 g / a), and the height of
the column at the back wall H = h / a against tau = t sqrt(g / a), square column (n^2 = 1),
a = 2.25 in. `martin_moyce_rms` is the root mean square over a table of the difference between the
simulated and measured values at the table's times.
"""

import math
import struct

G = 9.81

# Martin & Moyce (1952), square column, a = 2.25 in: surge front Z = z/a at T = t sqrt(2g/a). The
# point (T, Z) = (0, 1) is left out: it holds at t = 0 by construction.
MM_FRONT_T = [0.41, 0.84, 1.19, 1.43, 1.63, 1.82, 1.97, 2.20, 2.32, 2.50, 2.64, 2.82, 2.96]
MM_FRONT_Z = [1.11, 1.23, 1.44, 1.67, 1.89, 2.11, 2.33, 2.56, 2.78, 3.00, 3.22, 3.44, 3.67]
# Martin & Moyce (1952), square column, a = 2.25 in: column height H = h/a at tau = t sqrt(g/a)
# (h read in eighths of an inch: H steps by 1/18). Up to tau = 3.44, H = 0.22; their three later
# points (H = 0.17, 0.11, 0.06 at tau = 4.20, 5.25, 7.40) are a film thinner than 4 cells at the
# coarsest resolutions and would need a channel longer than 12 a.
MM_HEIGHT_TAU = [0.56, 0.77, 0.93, 1.08, 1.28, 1.46, 1.66, 1.84, 2.00, 2.21, 2.45, 2.70, 3.06, 3.44]
MM_HEIGHT_H = [0.94, 0.89, 0.83, 0.78, 0.72, 0.67, 0.61, 0.56, 0.50, 0.44, 0.39, 0.33, 0.28, 0.22]


def sloshing_frequency(length, depth, g=G):
    """Linear first-mode frequency [Hz]: omega^2 = g k tanh(k H), k = pi / L (Lamb 1932, sec. 227)."""
    k = math.pi / length
    return math.sqrt(g * k * math.tanh(k * depth)) / (2 * math.pi)


def mode_amplitude(xs, etas, weights, length):
    """A of the weighted least-squares fit eta(x) = c + A cos(pi x / L) over the samples."""
    k = math.pi / length
    s = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
    for x, e, w in zip(xs, etas, weights):
        c = math.cos(k * x)
        s[0][0] += w
        s[0][1] += w * c
        s[1][1] += w * c * c
        s[0][2] += w * e
        s[1][2] += w * c * e
    det = s[0][0] * s[1][1] - s[0][1] ** 2
    if det <= 0:
        raise ValueError("mode_amplitude: fewer than two distinct surface samples")
    return (s[0][0] * s[1][2] - s[0][1] * s[0][2]) / det


def _peak(t, y, i):
    """Time and value of the extremum of the parabola through samples i-1, i, i+1."""
    t0, t1, t2 = t[i - 1], t[i], t[i + 1]
    y0, y1, y2 = y[i - 1], y[i], y[i + 1]
    d = (t0 - t1) * (t0 - t2) * (t1 - t2)
    a = (t2 * (y1 - y0) + t1 * (y0 - y2) + t0 * (y2 - y1)) / d
    b = (t2 * t2 * (y0 - y1) + t1 * t1 * (y2 - y0) + t0 * t0 * (y1 - y2)) / d
    if a == 0:
        return t1, y1
    tp = min(max(-b / (2 * a), t0), t2)
    c = y1 - a * t1 * t1 - b * t1
    return tp, a * tp * tp + b * tp + c


def sloshing_frequency_and_decay(t, amplitude):
    """(frequency [Hz], amplitude change per period [-], number of extrema) of a mode amplitude A(t).

    Frequency: (crossings - 1) / (2 (last crossing - first crossing)) over the zero crossings of A.
    Change per period: (|A_last| / |A_first|)^(1 / periods) - 1 over the extrema after the first
    crossing (negative: decay), the extrema half a period apart."""
    crossings = [t[i - 1] + (t[i] - t[i - 1]) * amplitude[i - 1] / (amplitude[i - 1] - amplitude[i])
                 for i in range(1, len(t)) if (amplitude[i - 1] > 0) != (amplitude[i] > 0)]
    if len(crossings) < 3:
        raise ValueError(f"{len(crossings)} zero crossings of the mode amplitude: fewer than 3")
    frequency = (len(crossings) - 1) / (2 * (crossings[-1] - crossings[0]))
    extrema = []
    for i in range(1, len(t) - 1):
        if t[i] <= crossings[0]:
            continue
        a0, a1, a2 = abs(amplitude[i - 1]), abs(amplitude[i]), abs(amplitude[i + 1])
        if a1 >= a0 and a1 > a2 and (amplitude[i - 1] > 0) == (amplitude[i] > 0) == (amplitude[i + 1] > 0):
            extrema.append(_peak(t, amplitude, i))
    if len(extrema) < 2:
        raise ValueError(f"{len(extrema)} extrema of the mode amplitude after its first zero crossing: fewer than 2")
    periods = (extrema[-1][0] - extrema[0][0]) * frequency
    change = (abs(extrema[-1][1]) / abs(extrema[0][1])) ** (1.0 / periods) - 1.0
    return frequency, change, len(extrema)


def interpolate(ts, ys, t):
    """ys linearly interpolated at t (ts increasing); None outside [ts[0], ts[-1]]."""
    if not ts or t < ts[0] or t > ts[-1]:
        return None
    lo, hi = 0, len(ts) - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if ts[mid] <= t:
            lo = mid
        else:
            hi = mid
    if ts[hi] == ts[lo]:
        return ys[lo]
    return ys[lo] + (ys[hi] - ys[lo]) * (t - ts[lo]) / (ts[hi] - ts[lo])


def martin_moyce_rms(t, value, a, which, g=G):
    """(rms, largest |difference|) of the simulated front z(t) (which = "front") or column height
    h(t) (which = "height") [m] against Martin & Moyce's table, both made dimensionless by a."""
    if which == "front":
        scale, times, ref = math.sqrt(2 * g / a), MM_FRONT_T, MM_FRONT_Z
    elif which == "height":
        scale, times, ref = math.sqrt(g / a), MM_HEIGHT_TAU, MM_HEIGHT_H
    else:
        raise ValueError(f"martin_moyce_rms: which = {which!r}")
    diffs = []
    for tt, r in zip(times, ref):
        v = interpolate(t, value, tt / scale)
        if v is None:
            raise ValueError(f"the run ends at t = {t[-1]:.4f} s, before the table's {tt / scale:.4f} s")
        diffs.append(v / a - r)
    return math.sqrt(sum(d * d for d in diffs) / len(diffs)), max(abs(d) for d in diffs)


def read_ply(path):
    """(vertices [(x, y, z)], triangles [(i, j, k)]) of a PLY file as tetfsi writes it (binary little
    endian, float x y z and optional float vx vy vz per vertex, uchar-int face lists), or ASCII."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    fmt = header[1].split()[1]
    nv = nf = 0
    props = []
    element = None
    for line in header:
        words = line.split()
        if words[:1] == ["element"]:
            element = words[1]
            if element == "vertex":
                nv = int(words[2])
            elif element == "face":
                nf = int(words[2])
        elif words[:1] == ["property"] and element == "vertex":
            if words[1] != "float":
                raise ValueError(f"{path}: vertex property type {words[1]} (float expected)")
            props.append(words[2])
    if fmt == "ascii":
        lines = data[end:].decode("ascii").split("\n")
        vertices = [tuple(float(v) for v in lines[i].split()[:3]) for i in range(nv)]
        triangles = [tuple(int(v) for v in lines[nv + i].split()[1:4]) for i in range(nf)]
        return vertices, triangles
    if fmt != "binary_little_endian":
        raise ValueError(f"{path}: PLY format {fmt}")
    stride = 4 * len(props)
    flat = struct.unpack_from(f"<{nv * len(props)}f", data, end)
    vertices = [tuple(flat[i * len(props):i * len(props) + 3]) for i in range(nv)]
    off = end + nv * stride
    triangles = []
    for _ in range(nf):
        if data[off] != 3:
            raise ValueError(f"{path}: a face with {data[off]} vertices")
        triangles.append(struct.unpack_from("<3i", data, off + 1))
        off += 13
    return vertices, triangles


def top_surface_samples(vertices, triangles, up=1, min_normal=0.5):
    """(x, elevation, horizontal area) of the triangles of a closed liquid surface that face up
    (normal's up component above `min_normal`): the free surface without the wetted walls and floor."""
    xs, etas, areas = [], [], []
    for i, j, k in triangles:
        p, q, r = vertices[i], vertices[j], vertices[k]
        u = [q[m] - p[m] for m in range(3)]
        v = [r[m] - p[m] for m in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        norm = math.sqrt(sum(c * c for c in n))
        if norm == 0 or n[up] / norm <= min_normal:
            continue
        xs.append((p[0] + q[0] + r[0]) / 3)
        etas.append((p[up] + q[up] + r[up]) / 3)
        areas.append(0.5 * n[up])
    return xs, etas, areas
