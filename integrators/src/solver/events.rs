//! Event location for the driver: evaluating the event functions, detecting sign changes, and
//! locating the earliest crossing in a step on the method's dense output (bisection with the
//! Illinois variant of regula falsi).

use crate::error::ErrorKind;
use crate::method::Method;
use crate::problem::Problem;

/// Sign-change test: `a` nonzero and `b` zero or of the other sign.
pub(super) fn fires(a: f64, b: f64) -> bool {
    a != 0.0 && (b == 0.0 || (a > 0.0) != (b > 0.0))
}

/// Evaluates the event functions, checking their number and finiteness.
pub(super) fn eval_events<P: Problem>(
    p: &mut P,
    t: f64,
    y: &[f64],
    g: &mut Vec<f64>,
) -> Result<(), ErrorKind> {
    let ne = p.num_events();
    g.clear();
    g.resize(ne, 0.0);
    if ne == 0 {
        return Ok(());
    }
    p.events(t, y, g);
    if let Some(i) = crate::linalg::first_non_finite(g) {
        return Err(ErrorKind::Residual(format!(
            "event function {i} is not finite at t = {t}"
        )));
    }
    Ok(())
}

/// A located event.
pub(super) struct Located {
    /// Event time (right end of the final bracket).
    pub(super) t: f64,
    /// Functions that changed sign in the final bracket.
    pub(super) fired: Vec<usize>,
    /// Event-function values at `t`.
    pub(super) g: Vec<f64>,
    /// Sign of each function just after its crossing.
    pub(super) post: Vec<f64>,
    /// The fired functions whose root lies just after `t` (within the tolerance): still on
    /// their pre-crossing side at `t`, so the driver treats them as zero after the event.
    pub(super) ahead: Vec<usize>,
}

/// Locates the earliest sign change in `(a, b]` on the dense output.
#[allow(clippy::too_many_arguments)]
pub(super) fn locate<P: Problem>(
    p: &mut P,
    m: &dyn Method,
    tol: f64,
    mut a: f64,
    mut ga: Vec<f64>,
    mut b: f64,
    mut gb: Vec<f64>,
    ybuf: &mut Vec<f64>,
    ypbuf: &mut Vec<f64>,
) -> Result<Located, ErrorKind> {
    let n = m.y().len();
    ybuf.resize(n, 0.0);
    ypbuf.resize(n, 0.0);
    let mut gm = Vec::new();
    // the step's end, for the roots just after the final bracket (below)
    let end = b;
    let g_end = gb.clone();
    // Illinois weights on the retained endpoint values
    let (mut wa, mut wb) = (1.0f64, 1.0f64);
    let mut last_side = 0i8; // -1: a retained last time, +1: b retained
    for _ in 0..200 {
        let width = b - a;
        let tol_eff = tol.max(4.0 * f64::EPSILON * a.abs().max(b.abs()));
        if width <= tol_eff {
            break;
        }
        // earliest secant root among the functions changing sign in [a, b]
        let mut tm = b;
        for i in 0..ga.len() {
            if fires(ga[i], gb[i]) {
                let fa = ga[i] * wa;
                let fb = gb[i] * wb;
                let s = if fa != fb {
                    a + width * fa / (fa - fb)
                } else {
                    a + 0.5 * width
                };
                if s.is_finite() {
                    tm = tm.min(s);
                }
            }
        }
        // keep the point strictly inside, at least tol/2 from either end
        let margin = (0.5 * tol_eff).min(0.25 * width);
        tm = tm.clamp(a + margin, b - margin);
        if !(tm > a && tm < b) {
            tm = a + 0.5 * width;
            if !(tm > a && tm < b) {
                break;
            }
        }
        m.interpolate(tm, ybuf, ypbuf);
        eval_events(p, tm, ybuf, &mut gm)?;
        if gm.len() != ga.len() {
            return Err(ErrorKind::Residual(
                "number of event functions changed during root finding".into(),
            ));
        }
        let left = (0..ga.len()).any(|i| fires(ga[i], gm[i]));
        if left {
            b = tm;
            std::mem::swap(&mut gb, &mut gm);
            wb = 1.0;
            if last_side == -1 {
                wa *= 0.5;
            } else {
                wa = 1.0;
            }
            last_side = -1;
        } else {
            a = tm;
            std::mem::swap(&mut ga, &mut gm);
            wa = 1.0;
            if last_side == 1 {
                wb *= 0.5;
            } else {
                wb = 1.0;
            }
            last_side = 1;
        }
    }
    // Roots within the tolerance of each other fire together, wherever the final bracket's
    // end falls between them: the functions that change sign in (t*, t* + tol] fire too
    // (cells of a uniform line reach their division threshold 5e-13 apart by rounding; split
    // over two events, the second restart made their lineages part by 2.6e-7 in time).
    let tol_eff = tol.max(4.0 * f64::EPSILON * a.abs().max(b.abs()));
    let reach = (b + tol_eff).min(end);
    let g_reach = if reach <= b {
        None
    } else if reach == end {
        Some(g_end)
    } else {
        m.interpolate(reach, ybuf, ypbuf);
        eval_events(p, reach, ybuf, &mut gm)?;
        (gm.len() == ga.len()).then_some(gm)
    };
    let mut fired = Vec::new();
    let mut ahead = Vec::new();
    // the sign just after each crossing (for a function fired ahead, the other side of t*'s)
    let mut post: Vec<f64> = (0..ga.len())
        .map(|i| {
            if gb[i] != 0.0 {
                gb[i].signum()
            } else {
                -ga[i].signum()
            }
        })
        .collect();
    for i in 0..ga.len() {
        if fires(ga[i], gb[i]) {
            fired.push(i);
        } else if g_reach.as_ref().is_some_and(|g| fires(gb[i], g[i])) {
            fired.push(i);
            ahead.push(i);
            post[i] = -gb[i].signum();
        }
    }
    Ok(Located {
        t: b,
        fired,
        g: gb,
        post,
        ahead,
    })
}

/// Masks fired functions that sit at zero or on their post-crossing side after an event, and
/// those fired just ahead of their root (`ahead`), so that no root fires twice.
pub(super) fn mask_fired(g: &mut [f64], fired: &[usize], post: &[f64], ahead: &[usize]) {
    for &i in fired {
        if i < g.len() && i < post.len() && (g[i] == 0.0 || g[i].signum() == post[i]) {
            g[i] = 0.0;
        }
    }
    for &i in ahead {
        if i < g.len() {
            g[i] = 0.0;
        }
    }
}
