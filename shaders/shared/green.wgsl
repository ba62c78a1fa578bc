// Steady-sliding Green's function of a square source cell in f32 (paper
// Eq. 4 and Eq. 6; physics.md section 3), shared by the kernels that need it
// (coefficients, adaptive_coefficients, adaptive_matvec; `compose` adds it
// to those only). Everything is in units of the source cell side s:
// K(d; s) = s T(d / s) with memory lengths l_k / s, and the host multiplies
// by (1 - nu^2)/pi * (length unit) * (total compliance).
//
// L: Love's closed form within one cell of the source cell; beyond, a
// tensor Gauss-Legendre rule over the source cell whose order falls with the
// distance (the closed form cancels like eps (r/a)^2 in f32).
// Line integral: a fixed composite 8-point Gauss-Legendre rule on panels
// that split at the special points (s = 0, the crossings of the lines
// x = +-1/2 and y = +-1/2 where L has kinks, the closest approach to the
// source) and are graded geometrically (ratio 2) towards each of them; the
// panels at s = 0 reach below l_min / 8, the tail doubles until 20 l_max.
// terms[k] = (w_k, 1 / l_k), w_k the compliance fraction of creep term k and
// l_k = v tau_k in the unit length of the kernel.
// Rectangular source cells (physics.md section 11): the unit length is the
// side along x and the cell is 1 x `cell_aspect` (a_y / a_x); kernels that
// leave it at 1 have square cells.

@group(0) @binding(1) var<storage, read> terms: array<vec2<f32>>;

// Side of the source cell along y in units of its side along x.
var<private> cell_aspect: f32 = 1.0;

// Inverse memory lengths (per source cell) above this act as relaxed.
const RELAXED_INV: f32 = 1e7;

var<private> gl_x: array<f32, 8> = array<f32, 8>(
    -0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
    0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363);
var<private> gl_w: array<f32, 8> = array<f32, 8>(
    0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
    0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763);
var<private> gl6_x: array<f32, 6> = array<f32, 6>(
    -0.9324695142031521, -0.6612093864662645, -0.2386191860831969,
    0.2386191860831969, 0.6612093864662645, 0.9324695142031521);
var<private> gl6_w: array<f32, 6> = array<f32, 6>(
    0.1713244923791704, 0.3607615730481386, 0.4679139345726910,
    0.4679139345726910, 0.3607615730481386, 0.1713244923791704);
var<private> gl4_x: array<f32, 4> = array<f32, 4>(
    -0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526);
var<private> gl4_w: array<f32, 4> = array<f32, 4>(
    0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538);

fn asinh_f(x: f32) -> f32 {
    let ax = abs(x);
    var r: f32;
    if (ax > 1e18) {
        r = log(2.0 * ax);
    } else {
        r = log(ax + sqrt(ax * ax + 1.0));
    }
    return select(r, -r, x < 0.0);
}

// F(X, Y) = X asinh(Y/|X|) + Y asinh(X/|Y|), zero terms on the axes.
fn corner(x: f32, y: f32) -> f32 {
    var v = 0.0;
    if (x != 0.0) {
        v = v + x * asinh_f(y / abs(x));
    }
    if (y != 0.0) {
        v = v + y * asinh_f(x / abs(y));
    }
    return v;
}

// Love's closed form over the unit cell (1 x cell_aspect).
fn love_near(x: f32, y: f32) -> f32 {
    let hy = 0.5 * cell_aspect;
    let x1 = x + 0.5;
    let x2 = x - 0.5;
    let y1 = y + hy;
    let y2 = y - hy;
    return corner(x1, y1) - corner(x2, y1) - corner(x1, y2) + corner(x2, y2);
}

// Tensor Gauss-Legendre rule of 1/r over the unit cell.
fn love_gl8(x: f32, y: f32) -> f32 {
    var s = 0.0;
    for (var i = 0u; i < 8u; i = i + 1u) {
        let dx = x - 0.5 * gl_x[i];
        for (var j = 0u; j < 8u; j = j + 1u) {
            let dy = y - 0.5 * cell_aspect * gl_x[j];
            s = s + gl_w[i] * gl_w[j] * inverseSqrt(dx * dx + dy * dy);
        }
    }
    return 0.25 * cell_aspect * s;
}

fn love_gl6(x: f32, y: f32) -> f32 {
    var s = 0.0;
    for (var i = 0u; i < 6u; i = i + 1u) {
        let dx = x - 0.5 * gl6_x[i];
        for (var j = 0u; j < 6u; j = j + 1u) {
            let dy = y - 0.5 * cell_aspect * gl6_x[j];
            s = s + gl6_w[i] * gl6_w[j] * inverseSqrt(dx * dx + dy * dy);
        }
    }
    return 0.25 * cell_aspect * s;
}

fn love_gl4(x: f32, y: f32) -> f32 {
    var s = 0.0;
    for (var i = 0u; i < 4u; i = i + 1u) {
        let dx = x - 0.5 * gl4_x[i];
        for (var j = 0u; j < 4u; j = j + 1u) {
            let dy = y - 0.5 * cell_aspect * gl4_x[j];
            s = s + gl4_w[i] * gl4_w[j] * inverseSqrt(dx * dx + dy * dy);
        }
    }
    return 0.25 * cell_aspect * s;
}

// L(x, y) over the unit cell: closed form within one (longer) side of the
// cell, Gauss-Legendre of decreasing order beyond (error below 1e-8
// relative: the integrand's complex singularities lie at least the
// distance to the cell away); distances in units of the longer side.
fn love(x: f32, y: f32) -> f32 {
    let q = max(abs(vec2<f32>(x, y)) - vec2<f32>(0.5, 0.5 * cell_aspect), vec2<f32>(0.0, 0.0));
    let dist = length(q) / max(1.0, cell_aspect);
    var v = 0.0;
    if (dist < 1.0) {
        v = love_near(x, y);
    } else if (dist < 2.5) {
        v = love_gl8(x, y);
    } else if (dist < 8.0) {
        v = love_gl6(x, y);
    } else if (dist < 40.0) {
        v = love_gl4(x, y);
    } else {
        let dx = 0.2886751345948129;
        var s = 0.0;
        for (var i = 0u; i < 2u; i = i + 1u) {
            for (var j = 0u; j < 2u; j = j + 1u) {
                let px = x - select(-dx, dx, i == 1u);
                let py = y - cell_aspect * select(-dx, dx, j == 1u);
                s = s + inverseSqrt(px * px + py * py);
            }
        }
        v = 0.25 * cell_aspect * s;
    }
    return v;
}

// Inverse memory length (in source cells) of term k for a source `size`
// times the unit length of `terms`.
fn inv_len(k: u32, size: f32) -> f32 {
    return terms[k].y * size;
}

// Memory weight phi(s) = sum_k w_k (1/l_k) exp(-s/l_k) over the active terms
// (those not relaxed at this source size).
fn phi(s: f32, count: u32, size: f32) -> f32 {
    var v = 0.0;
    for (var k = 0u; k < count; k = k + 1u) {
        let inv = inv_len(k, size);
        let z = s * inv;
        if (inv <= RELAXED_INV && z < 40.0) {
            v = v + terms[k].x * inv * exp(-z);
        }
    }
    return v;
}

// 8-point Gauss-Legendre over [s0, s1] of phi(s) L(X + s e).
fn panel(s0: f32, s1: f32, x: vec2<f32>, e: vec2<f32>, count: u32, size: f32) -> f32 {
    let c = 0.5 * (s0 + s1);
    let h = 0.5 * (s1 - s0);
    var acc = 0.0;
    for (var i = 0u; i < 8u; i = i + 1u) {
        let s = c + h * gl_x[i];
        let p = x + s * e;
        acc = acc + gl_w[i] * phi(s, count, size) * love(p.x, p.y);
    }
    return h * acc;
}

// Integral over [c, c + dir h] on panels graded towards c (ratio 2,
// `levels` levels, the innermost panel [c, c + dir h 2^-levels]).
fn graded(c: f32, dir: f32, h: f32, levels: u32, x: vec2<f32>, e: vec2<f32>, count: u32, size: f32) -> f32 {
    var acc = 0.0;
    var outer = h;
    for (var j = 0u; j < levels; j = j + 1u) {
        let inner = 0.5 * outer;
        acc = acc + panel(c + dir * inner, c + dir * outer, x, e, count, size) * dir;
        outer = inner;
    }
    acc = acc + panel(c, c + dir * outer, x, e, count, size) * dir;
    return acc;
}

fn levels_for(h: f32, l_min: f32) -> u32 {
    let want = ceil(log2(max(8.0 * h / l_min, 1.0)));
    return u32(clamp(want, 12.0, 60.0));
}

// The dimensionless coefficient T(X) of a unit source cell at offset X
// (cell units), paper Eq. 4 and Eq. 6 (physics.md section 3):
//   T(X) = g L(X) + sum_k w_k int_0^inf ds (1/l_k) exp(-s/l_k) L(X + s e),
// for a source whose side is `size` times the unit length of the memory
// lengths in `terms` (l_k in source cells = l_k / size). Terms with
// l_k / size < 1e-7 act as relaxed compliance (added to `instantaneous`, the
// glassy-plus-relaxed fraction g); terms with l_k > 1e7 (|X| + 1) act as
// glassy (no memory contribution; the dropped part is below 2e-6 relative).
// `count` terms are read; `e` is the unit sliding direction.
fn unit_coefficient(x: vec2<f32>, e: vec2<f32>, instantaneous: f32, count: u32, size: f32) -> f32 {
    // Active terms at this offset: those with l_k <= 1e7 (|X| + 1) (longer
    // memories act as glassy: the dropped part is below 2e-6 relative).
    let r = length(x) + 1.0;
    var g = instantaneous;
    var l_min = 3.0e38;
    var l_max = 0.0;
    var has_memory = false;
    for (var k = 0u; k < count; k = k + 1u) {
        let inv = inv_len(k, size);
        let l = 1.0 / inv;
        if (inv > RELAXED_INV) {
            g = g + terms[k].x;
        } else if (l <= 1e7 * r) {
            l_min = min(l_min, l);
            l_max = max(l_max, l);
            has_memory = true;
        }
    }
    var value = 0.0;
    if (has_memory) {
        // Special points, sorted, strictly inside (0, s_end).
        let s_end = 20.0 * l_max;
        var pts: array<f32, 8>;
        var np = 1u;
        pts[0] = 0.0;
        var cand: array<f32, 5>;
        cand[0] = select(-1.0, (-0.5 - x.x) / e.x, e.x != 0.0);
        cand[1] = select(-1.0, (0.5 - x.x) / e.x, e.x != 0.0);
        cand[2] = select(-1.0, (-0.5 * cell_aspect - x.y) / e.y, e.y != 0.0);
        cand[3] = select(-1.0, (0.5 * cell_aspect - x.y) / e.y, e.y != 0.0);
        cand[4] = -dot(x, e);
        for (var k = 0u; k < 5u; k = k + 1u) {
            let s = cand[k];
            if (s > 1e-6 && s < s_end) {
                // Insert in order unless it coincides with a point.
                var dup = false;
                for (var m = 0u; m < np; m = m + 1u) {
                    if (abs(pts[m] - s) <= 1e-6 * (1.0 + s)) {
                        dup = true;
                    }
                }
                if (!dup) {
                    var m = np;
                    while (m > 0u && pts[m - 1u] > s) {
                        pts[m] = pts[m - 1u];
                        m = m - 1u;
                    }
                    pts[m] = s;
                    np = np + 1u;
                }
            }
        }
        var mem = 0.0;
        for (var k = 0u; k + 1u < np; k = k + 1u) {
            let a = pts[k];
            let b = pts[k + 1u];
            let h = 0.5 * (b - a);
            var la = 12u;
            if (k == 0u) {
                la = levels_for(h, l_min);
            }
            mem = mem + graded(a, 1.0, h, la, x, e, count, size);
            mem = mem + graded(b, -1.0, h, 12u, x, e, count, size);
        }
        // Tail from the last special point: graded over one cell, then
        // doubling panels until 20 l_max.
        let c = pts[np - 1u];
        var lt = 12u;
        if (np == 1u) {
            lt = levels_for(1.0, l_min);
        }
        mem = mem + graded(c, 1.0, 1.0, lt, x, e, count, size);
        var s0 = c + 1.0;
        var len = 1.0;
        while (s0 < c + s_end) {
            mem = mem + panel(s0, s0 + len, x, e, count, size);
            s0 = s0 + len;
            len = 2.0 * len;
        }
        value = mem;
    }
    return g * love(x.x, x.y) + value;
}
