//! The constants of Radau IIA of order 5: nodes, the inverse of the Butcher matrix and its
//! eigen-decomposition (one real and one complex pair), and the embedded error estimate's weights.

/// Method constants (Hairer & Wanner II, Table IV.5.6 and RADAU5's `CONSTANTS`).
#[derive(Clone, Debug)]
pub(super) struct Consts {
    pub(super) c: [f64; 3],
    pub(super) a_inv: [[f64; 3]; 3],
    pub(super) t: [[f64; 3]; 3],
    pub(super) ti: [[f64; 3]; 3],
    pub(super) gamma: f64,
    pub(super) alpha: f64,
    pub(super) beta: f64,
    pub(super) dd: [f64; 3],
}

/// The Radau IIA (order 5) Butcher matrix, from its exact formulas (Hairer & Wanner II,
/// Table IV.5.6).
pub(super) fn radau_a() -> [[f64; 3]; 3] {
    let s6 = 6f64.sqrt();
    [
        [
            (88.0 - 7.0 * s6) / 360.0,
            (296.0 - 169.0 * s6) / 1800.0,
            (-2.0 + 3.0 * s6) / 225.0,
        ],
        [
            (296.0 + 169.0 * s6) / 1800.0,
            (88.0 + 7.0 * s6) / 360.0,
            (-2.0 - 3.0 * s6) / 225.0,
        ],
        [(16.0 - s6) / 36.0, (16.0 + s6) / 36.0, 1.0 / 9.0],
    ]
}

/// Inverse of a 3×3 matrix (cofactors).
fn inv3(m: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let [[a, b, c], [d, e, f], [g, h, i]] = *m;
    let det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
    [
        [
            (e * i - f * h) / det,
            (c * h - b * i) / det,
            (b * f - c * e) / det,
        ],
        [
            (f * g - d * i) / det,
            (a * i - c * g) / det,
            (c * d - a * f) / det,
        ],
        [
            (d * h - e * g) / det,
            (b * g - a * h) / det,
            (a * e - b * d) / det,
        ],
    ]
}

impl Consts {
    pub(super) fn new() -> Self {
        let s6 = 6f64.sqrt();
        let c1 = (4.0 - s6) / 10.0;
        let c2 = (4.0 + s6) / 10.0;
        // Eigenvalues of A⁻¹ (RADAU5): real γ̂ = 1/u1 ... and the pair α̂ ± iβ̂.
        let cbrt81 = 81f64.cbrt();
        let cbrt9 = 9f64.cbrt();
        let gamma = 30.0 / (6.0 + cbrt81 - cbrt9);
        let a0 = (12.0 - cbrt81 + cbrt9) / 60.0;
        let b0 = (cbrt81 + cbrt9) * 3f64.sqrt() / 60.0;
        let cno = a0 * a0 + b0 * b0;
        // Eigenvectors T and T⁻¹ as published in RADAU5 (normalised with last row (·, 1, 0));
        // verified against the exact A in the unit tests (T⁻¹ A⁻¹ T = diag(γ̂, [[α̂,−β̂],[β̂,α̂]])).
        #[allow(clippy::excessive_precision)]
        let t = [
            [
                9.123_239_487_089_294_279_2e-2,
                -0.141_255_295_020_954_208_43,
                -3.002_919_410_514_742_449_2e-2,
            ],
            [
                0.241_717_932_707_107_018_96,
                0.204_129_352_293_799_931_99,
                0.382_942_112_757_261_937_79,
            ],
            [0.966_048_182_615_092_936_19, 1.0, 0.0],
        ];
        #[allow(clippy::excessive_precision)]
        let ti = [
            [
                4.325_579_890_063_155_351,
                0.339_199_251_815_809_869_54,
                0.541_770_539_935_874_871_19,
            ],
            [
                -4.178_718_591_551_904_727_3,
                -0.327_682_820_761_062_387_08,
                0.476_623_554_500_550_451_96,
            ],
            [
                -0.502_872_634_945_786_875_95,
                2.571_926_949_855_605_429_2,
                -0.596_039_204_828_224_924_97,
            ],
        ];
        Self {
            c: [c1, c2, 1.0],
            a_inv: inv3(&radau_a()),
            t,
            ti,
            gamma,
            alpha: a0 / cno,
            beta: b0 / cno,
            dd: [
                -(13.0 + 7.0 * s6) / 3.0,
                (-13.0 + 7.0 * s6) / 3.0,
                -1.0 / 3.0,
            ],
        }
    }
}
