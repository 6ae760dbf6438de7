//! The Newton step of the direct method: a linear-quadratic problem along the trajectory with
//! a fixed terminal state, solved by a Riccati recursion in `O(N)` (as acados/HPIPM do for
//! their stage-structured QPs).
//!
//! ```text
//! minimise  Σ_k ½ (δs_k, δu_k)ᵀ Q_k (δs_k, δu_k) + r_kᵀ δu_k
//! subject to δs_{k+1} = A_k δs_k + B_k δu_k,   δs_0 = 0,   δs_N = e
//! ```
//!
//! `Q_k` is the Hessian of the Lagrangian at stage `k` (from [`super::stage`], the cost's
//! included by [`super::linearisation`]) plus `δ·I` on the controls (a regularisation
//! `δ ≥ 0`). For a terminal
//! multiplier `ν` the problem without the terminal constraint but with the extra cost `νᵀδs_N`
//! has the value function `½δsᵀP_kδs + p_kᵀδs`, `p_k = p⁰_k + Π_k ν`, computed backwards from
//! `P_N = 0, p⁰_N = 0, Π_N = I`:
//!
//! ```text
//! Q̂_uu = Q_uu + BᵀPB,  Q̂_us = Q_us + BᵀPA,  Q̂_ss = Q_ss + AᵀPA
//! K = −Q̂_uu⁻¹Q̂_us,  d⁰ = −Q̂_uu⁻¹(r + Bᵀp⁰),  D = −Q̂_uu⁻¹BᵀΠ
//! P ← Q̂_ss + Q̂_usᵀK,  p⁰ ← (A + BK)ᵀp⁰ + Kᵀr,  Π ← (A + BK)ᵀΠ
//! ```
//!
//! The end of the optimal trajectory is `δs_N = σ + Mν`; `ν = M⁻¹(e − σ)` meets the terminal
//! constraint and is the QP's multiplier of it. `σ` and `M` are the gradient and Hessian in
//! `ν` of the optimal value (its constant term `v_k = v_{k+1} − ½q̂ᵀQ̂_uu⁻¹q̂`, `q̂ = r + Bᵀp`),
//! so they are sums over the backward pass, `σ = Σ_k D_kᵀq̂⁰_k`, `M = −Σ_k D_kᵀQ̂_uu D_k`, with
//! no forward propagation through the closed loop `A + BK` (which is unstable where `H` is
//! indefinite).
//!
//! **Inertia.** The backward recursion is a block `LDLᵀ` factorisation of the reduced Hessian
//! `H` (controls only, states eliminated), so `H` has as many negative eigenvalues as the
//! pivots `Q̂_uu` together; and `M = −G H⁻¹ Gᵀ` with `G = ∂δs_N/∂δu`. The QP is convex on the
//! constraint's null space (the second-order sufficient condition when `Q` is the exact
//! Hessian and the step is zero) exactly when the KKT matrix has `m = 5` negative eigenvalues,
//! i.e. `neg(H) + neg(M) = 5` (Haynsworth inertia additivity; Gould 1985).

use super::constraints::joint_limit::ControlMap;
use super::settings::{PIVOT, REFINE_GAIN, REFINE_MISS, REFINE_PASSES, SINGULAR};
use super::stage::Linearised;
use nalgebra::{
    Matrix2, Matrix2x3, Matrix2x5, Matrix3, Matrix3x2, Matrix3x5, Matrix5, SymmetricEigen, Vector2,
    Vector3, Vector5,
};

/// The coordinates `(α1, α2, θ)` of a state `(α1, α2, x, y, θ)`: the ones the dynamics and
/// the stage Hessians depend on.
const A_IDX: [usize; 3] = [0, 1, 4];
/// The position `(x, y)`, which only accumulates.
const P_IDX: [usize; 2] = [2, 3];

/// One stage split by [`A_IDX`] and [`P_IDX`]: `δa' = Āδa + B̄δu`, `δp' = δp + Cδa + Dδu`.
struct Split {
    a: Matrix3<f64>,
    b: Matrix3x2<f64>,
    c: Matrix2x3<f64>,
    d: Matrix2<f64>,
    qaa: Matrix3<f64>,
    qau: Matrix3x2<f64>,
}

impl Split {
    fn new(l: &Linearised) -> Self {
        Split {
            a: Matrix3::from_fn(|i, j| l.a[(A_IDX[i], A_IDX[j])]),
            b: Matrix3x2::from_fn(|i, j| l.b[(A_IDX[i], j)]),
            c: Matrix2x3::from_fn(|i, j| l.a[(P_IDX[i], A_IDX[j])]),
            d: Matrix2::from_fn(|i, j| l.b[(P_IDX[i], j)]),
            qaa: Matrix3::from_fn(|i, j| l.hss[(A_IDX[i], A_IDX[j])]),
            qau: Matrix3x2::from_fn(|i, j| l.hsu[(A_IDX[i], j)]),
        }
    }
}

impl Split {
    /// The `ν`-dependence of the stage's linear terms, `q_a ∋ C_kᵀν_p` and `q_u ∋ D_kᵀν_p`, as
    /// matrices acting on `ν`.
    fn multiplier_terms(&self) -> (Matrix3x5<f64>, Matrix2x5<f64>) {
        let mut gamma = Matrix3x5::<f64>::zeros();
        let mut delta_u = Matrix2x5::<f64>::zeros();
        for (col, &pc) in P_IDX.iter().enumerate() {
            gamma.set_column(pc, &self.c.row(col).transpose());
            delta_u.set_column(pc, &self.d.row(col).transpose());
        }
        (gamma, delta_u)
    }
}

/// One stage of the LQ problem in the recursion's variables: the split dynamics and
/// Hessians, the control Hessian with the cost's, its regularisation `δ·I`, a unit pivot
/// for each control that is not free, and the linear terms on the controls and on `δa`.
struct Stage {
    split: Split,
    huu: Matrix2<f64>,
    reg: Matrix2<f64>,
    fixed_pivot: Matrix2<f64>,
    r: Vector2<f64>,
    qa: Vector3<f64>,
}

impl Stage {
    /// Stage `l` with linear term `r` and regularisation `delta`; with a
    /// substitution `δu = Sδv + Lδa` (`sub`), in `(δa, δv)`: dynamics `A + BL`, `BS`, the
    /// costs transformed, the linear term `rᵀδu = (Sr)ᵀδv + (Lᵀr)ᵀδa`.
    fn new(
        l: &Linearised,
        r: Vector2<f64>,
        delta: f64,
        sub: Option<(Matrix2<f64>, Matrix2x3<f64>)>,
    ) -> Self {
        let mut stage = Stage {
            split: Split::new(l),
            huu: l.huu,
            reg: Matrix2::identity() * delta,
            fixed_pivot: Matrix2::zeros(),
            r,
            qa: Vector3::zeros(),
        };
        if let Some((sm, lm)) = sub {
            let (st, huu) = (&mut stage.split, stage.huu);
            st.qaa += st.qau * lm + lm.transpose() * st.qau.transpose() + lm.transpose() * huu * lm;
            st.qau = (st.qau + lm.transpose() * huu) * sm;
            stage.huu = sm * huu * sm;
            stage.reg = sm * stage.reg * sm;
            stage.fixed_pivot = Matrix2::identity() - sm;
            stage.qa = lm.transpose() * r;
            stage.r = sm * r;
            st.a += st.b * lm;
            st.c += st.d * lm;
            st.b *= sm;
            st.d *= sm;
        }
        stage
    }
}

/// The inverse of a pivot `Q̂_uu` and its number of negative eigenvalues; `None` if it is
/// singular ([`PIVOT`]) or not finite.
fn pivot(quu: &Matrix2<f64>) -> Option<(Matrix2<f64>, usize)> {
    let det = quu.m11 * quu.m22 - quu.m12 * quu.m21;
    let scale = quu.m11.abs().max(quu.m22.abs()).max(quu.m12.abs());
    if det.abs() <= PIVOT * scale * scale || !det.is_finite() {
        return None;
    }
    let negative = if det < 0.0 {
        1
    } else if quu.m11 < 0.0 {
        2
    } else {
        0
    };
    Some((
        Matrix2::new(quu.m22, -quu.m12, -quu.m21, quu.m11) / det,
        negative,
    ))
}

/// The number of negative eigenvalues of `M`; `None` if `M` or `σ` is not finite or `M` is
/// singular ([`SINGULAR`]).
fn negative_eigenvalues(m: &Matrix5<f64>, sigma: &Vector5<f64>) -> Option<usize> {
    if !m.iter().chain(sigma.iter()).all(|v| v.is_finite()) {
        return None;
    }
    let sym = (m + m.transpose()) * 0.5;
    let eig = SymmetricEigen::new(sym).eigenvalues;
    let largest = eig.amax();
    if eig.iter().any(|e| e.abs() <= SINGULAR * largest) {
        return None;
    }
    Some(eig.iter().filter(|e| **e < 0.0).count())
}

/// `δu = S δv + L δa` for a stage's [`ControlMap`]: `S` keeps the free controls, `L` sets an
/// arc's entry control from the state (`δu_i = −δα_i/h`); fixed controls are zero.
fn substitution(map: &ControlMap, h: f64) -> (Matrix2<f64>, Matrix2x3<f64>) {
    let mut s = Matrix2::zeros();
    let mut l = Matrix2x3::zeros();
    for i in 0..2 {
        if map.free(i) {
            s[(i, i)] = 1.0;
        } else if map.entry[i] {
            l[(i, i)] = -1.0 / h;
        }
    }
    (s, l)
}

/// The factorisation of one LQ problem (see the module docs).
#[derive(Clone, Debug)]
pub struct Factor {
    /// Per stage, `δu = S δv + L δa` (none: `δu = δv`).
    subs: Option<Vec<(Matrix2<f64>, Matrix2x3<f64>)>>,
    k: Vec<Matrix2x3<f64>>,
    d0: Vec<Vector2<f64>>,
    d: Vec<Matrix2x5<f64>>,
    /// `σ` and `M` of `δs_N = σ + Mν`.
    sigma: Vector5<f64>,
    m: Matrix5<f64>,
    /// Negative eigenvalues of the reduced Hessian `H`.
    pub negative_h: usize,
    /// Negative eigenvalues of `M`.
    pub negative_m: usize,
}

impl Factor {
    /// Whether the QP is strictly convex on the terminal constraint's null space.
    pub fn convex(&self) -> bool {
        self.negative_h + self.negative_m == 5
    }

    /// Factorises the LQ problem with stages `lin`, control step `h`, regularisation `delta`
    /// and linear terms `r` (the Lagrangian's gradient for the Newton step). `None` if a pivot
    /// or `M` is singular.
    ///
    /// The position `p = (x, y)` enters the swimmer's dynamics only additively (`∂f/∂p` is
    /// the identity on `p` and zero elsewhere, and no Hessian involves `p`), so the value
    /// function does not depend on `δp`: the recursion runs on `a = (α1, α2, θ)` alone, and
    /// `ν_pᵀδp_N = Σ_k ν_pᵀ(C_kδa_k + D_kδu_k)` becomes stage terms linear in `ν`.
    ///
    /// With control maps (joint-limit arcs), each stage's controls are substituted,
    /// `δu = S δv + L δa`, and the recursion runs on `δv`: a fixed control gets a unit pivot
    /// and zero terms (so `δv_i = 0`), and the inertia is that of the reduced Hessian on the
    /// arcs' tangent space.
    pub fn new(
        lin: &[Linearised],
        r: &[Vector2<f64>],
        h: f64,
        delta: f64,
        maps: Option<&[ControlMap]>,
    ) -> Option<Self> {
        let n = lin.len();
        let subs: Option<Vec<_>> = maps.map(|m| m.iter().map(|c| substitution(c, h)).collect());
        let mut k = vec![Matrix2x3::zeros(); n];
        let mut d0 = vec![Vector2::zeros(); n];
        let mut d = vec![Matrix2x5::zeros(); n];
        let mut p = Matrix3::<f64>::zeros();
        let mut p0 = Vector3::<f64>::zeros();
        // p_N = ν_a: Π_N selects (ν_α1, ν_α2, ν_θ).
        let mut pi = Matrix3x5::<f64>::zeros();
        for (row, &col) in A_IDX.iter().enumerate() {
            pi[(row, col)] = 1.0;
        }
        let mut sigma = Vector5::<f64>::zeros();
        let mut m = Matrix5::<f64>::zeros();
        let mut negative_h = 0;
        for i in (0..n).rev() {
            let Stage {
                split: st,
                huu,
                reg,
                fixed_pivot,
                r: ri,
                qa,
            } = Stage::new(&lin[i], r[i], delta, subs.as_ref().map(|v| v[i]));
            let (a, b) = (&st.a, &st.b);
            let pa = p * a;
            let pb = p * b;
            let quu = huu + reg + fixed_pivot + b.transpose() * pb;
            let quu = (quu + quu.transpose()) * 0.5;
            let qua = st.qau.transpose() + pb.transpose() * a;
            let qaa = st.qaa + a.transpose() * pa;
            let (inv, negative) = pivot(&quu)?;
            negative_h += negative;
            let (gamma, delta_u) = st.multiplier_terms();
            let ki = -(inv * qua);
            let q0 = ri + b.transpose() * p0;
            let qnu = delta_u + b.transpose() * pi;
            let d0i = -(inv * q0);
            let di = -(inv * qnu);
            sigma += di.transpose() * q0;
            m -= di.transpose() * quu * di;
            p = qaa + qua.transpose() * ki;
            p = (p + p.transpose()) * 0.5;
            p0 = qa + a.transpose() * p0 + qua.transpose() * d0i;
            pi = gamma + a.transpose() * pi + qua.transpose() * di;
            k[i] = ki;
            d0[i] = d0i;
            d[i] = di;
        }
        let negative_m = negative_eigenvalues(&m, &sigma)?;
        Some(Factor {
            subs,
            k,
            d0,
            d,
            sigma,
            m,
            negative_h,
            negative_m,
        })
    }

    /// The step `δu` that reaches `δs_N = e`, and the terminal multiplier `ν`. With
    /// `linear = false` the linear terms are left out (a correction step: the least change,
    /// in the metric of `Q`, that moves the end by `e`).
    ///
    /// The controls come from the closed loop `δu = Kδs + d⁰ + Dν`, which is unstable where
    /// the reduced Hessian is indefinite: its rounding can leave the open-loop end `δs_N` of
    /// the computed `δu` off `e` by ~1e-10 relative on long horizons. So `ν` is refined with
    /// the open-loop end (`ν ← ν + M⁻¹(e − δs_N)`, at most [`REFINE_PASSES`] passes, while it helps).
    pub fn solve(
        &self,
        lin: &[Linearised],
        e: &Vector5<f64>,
        linear: bool,
    ) -> Option<(Vec<Vector2<f64>>, Vector5<f64>)> {
        let lu = self.m.lu();
        let rhs = if linear { e - self.sigma } else { *e };
        let mut nu = lu.solve(&rhs)?;
        let mut du = Vec::with_capacity(lin.len());
        let mut last_miss = f64::INFINITY;
        for pass in 0..=REFINE_PASSES {
            du.clear();
            let mut open = Vector5::zeros();
            for (i, l) in lin.iter().enumerate() {
                let da = Vector3::new(open[0], open[1], open[4]);
                let mut u = self.k[i] * da + self.d[i] * nu;
                if linear {
                    u += self.d0[i];
                }
                if let Some((sm, lm)) = self.subs.as_ref().map(|v| v[i]) {
                    u = sm * u + lm * da;
                }
                open = l.a * open + l.b * u;
                du.push(u);
            }
            let miss = e - open;
            let size = miss.amax();
            if pass == REFINE_PASSES
                || size <= REFINE_MISS * e.amax()
                || size >= REFINE_GAIN * last_miss
            {
                break;
            }
            last_miss = size;
            nu += lu.solve(&miss)?;
        }
        Some((du, nu))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector, Matrix5x2};

    /// A random LQ problem shaped like the swimmer's: the position (rows/columns 2, 3) only
    /// accumulates and enters no Hessian, and `δα' = δα + h δu` (so arcs can be imposed).
    fn random_problem(
        n: usize,
        h: f64,
        seed: u64,
    ) -> (Vec<Linearised>, Vec<Vector2<f64>>, Vector5<f64>) {
        let mut seed = seed;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let on_a = |i: usize| i != 2 && i != 3;
        let lin: Vec<Linearised> = (0..n)
            .map(|_| {
                let a = Matrix5::from_fn(|i, j| match (on_a(i), on_a(j)) {
                    _ if i == j => 1.0,
                    _ if i < 2 => 0.0,
                    (_, false) => 0.0,
                    _ => 0.5 * rnd(),
                });
                let b = Matrix5x2::from_fn(|i, j| match i {
                    0 | 1 if i == j => h,
                    0 | 1 => 0.0,
                    _ => rnd(),
                });
                let q = Matrix5::from_fn(|i, j| if on_a(i) && on_a(j) { 0.2 * rnd() } else { 0.0 });
                let hsu = Matrix5x2::from_fn(|i, _| if on_a(i) { 0.1 * rnd() } else { 0.0 });
                let huu = Matrix2::from_fn(|_, _| 0.1 * rnd());
                Linearised {
                    a,
                    b,
                    hss: q + q.transpose(),
                    hsu,
                    // The stage's Hessian with the effort's `h·I` (MODEL.md §4).
                    huu: huu + huu.transpose() + Matrix2::identity() * h,
                }
            })
            .collect();
        let r: Vec<Vector2<f64>> = (0..n).map(|_| Vector2::new(rnd(), rnd())).collect();
        let e = Vector5::from_fn(|_, _| rnd());
        (lin, r, e)
    }

    /// The dense KKT matrix and right-hand side of the LQ problem in the controls `δu`, with
    /// the terminal constraint and, per `maps`, `δu_{k,i} = 0` (fixed) or `δα_{k+1,i} = 0`
    /// (entry); the reduced Hessian `H` too.
    fn dense(
        lin: &[Linearised],
        r: &[Vector2<f64>],
        e: &Vector5<f64>,
        maps: Option<&[ControlMap]>,
    ) -> (DMatrix<f64>, DVector<f64>, DMatrix<f64>) {
        let n = lin.len();
        let nv = 2 * n;
        let mut s = vec![DMatrix::<f64>::zeros(5, nv)]; // δs_k as a function of δu
        for k in 0..n {
            let mut next =
                DMatrix::<f64>::from_fn(5, nv, |i, j| (lin[k].a.row(i) * s[k].column(j))[0]);
            for i in 0..5 {
                for j in 0..2 {
                    next[(i, 2 * k + j)] += lin[k].b[(i, j)];
                }
            }
            s.push(next);
        }
        let mut hm = DMatrix::<f64>::zeros(nv, nv);
        let mut g = DVector::<f64>::zeros(nv);
        for k in 0..n {
            let mut z = DMatrix::<f64>::zeros(7, nv);
            z.view_mut((0, 0), (5, nv)).copy_from(&s[k]);
            z[(5, 2 * k)] = 1.0;
            z[(6, 2 * k + 1)] = 1.0;
            let mut q = DMatrix::<f64>::zeros(7, 7);
            q.view_mut((0, 0), (5, 5)).copy_from(&lin[k].hss);
            q.view_mut((0, 5), (5, 2)).copy_from(&lin[k].hsu);
            q.view_mut((5, 0), (2, 5))
                .copy_from(&lin[k].hsu.transpose());
            q.view_mut((5, 5), (2, 2)).copy_from(&lin[k].huu);
            hm += z.transpose() * q * &z;
            g[2 * k] += r[k].x;
            g[2 * k + 1] += r[k].y;
        }
        let mut rows: Vec<DVector<f64>> = (0..5).map(|i| s[n].row(i).transpose()).collect();
        let mut rhs_c: Vec<f64> = e.iter().copied().collect();
        for (k, m) in maps.unwrap_or(&[]).iter().enumerate() {
            for i in 0..2 {
                if m.fixed[i] {
                    rows.push(DVector::from_fn(nv, |j, _| f64::from(j == 2 * k + i)));
                } else if m.entry[i] {
                    rows.push(s[k + 1].row(i).transpose());
                } else {
                    continue;
                }
                rhs_c.push(0.0);
            }
        }
        let m = rows.len();
        let mut kkt = DMatrix::<f64>::zeros(nv + m, nv + m);
        kkt.view_mut((0, 0), (nv, nv)).copy_from(&hm);
        for (c, row) in rows.iter().enumerate() {
            kkt.view_mut((0, nv + c), (nv, 1)).copy_from(row);
            kkt.view_mut((nv + c, 0), (1, nv))
                .copy_from(&row.transpose());
        }
        let mut rhs = DVector::<f64>::zeros(nv + m);
        rhs.rows_mut(0, nv).copy_from(&(-g));
        for (c, v) in rhs_c.iter().enumerate() {
            rhs[nv + c] = *v;
        }
        (kkt, rhs, hm)
    }

    /// A random LQ problem solved by the Riccati factorisation and by a dense KKT system.
    #[test]
    fn riccati_step_solves_the_dense_kkt_system() {
        let (n, h) = (6, 0.3);
        let (lin, r, e) = random_problem(n, h, 7);
        let f = Factor::new(&lin, &r, h, 0.0, None).unwrap();
        let (du, nu) = f.solve(&lin, &e, true).unwrap();
        let (kkt, rhs, hm) = dense(&lin, &r, &e, None);
        let nv = 2 * n;
        let sol = kkt.clone().lu().solve(&rhs).unwrap();
        for k in 0..n {
            assert!((du[k].x - sol[2 * k]).abs() < 1e-9);
            assert!((du[k].y - sol[2 * k + 1]).abs() < 1e-9);
        }
        for i in 0..5 {
            assert!((nu[i] - sol[nv + i]).abs() < 1e-9, "nu {i}");
        }
        // Inertia: the KKT matrix has neg(H) + neg(M) negative eigenvalues.
        let eig = kkt.symmetric_eigen().eigenvalues;
        let neg = eig.iter().filter(|v| **v < 0.0).count();
        assert_eq!(neg, f.negative_h + f.negative_m);
        let neg_h = hm
            .symmetric_eigen()
            .eigenvalues
            .iter()
            .filter(|v| **v < 0.0)
            .count();
        assert_eq!(neg_h, f.negative_h);
    }

    /// With joint-limit arcs (MODEL.md §9): the Riccati step with the controls substituted
    /// (fixed in the arc, the entry control set by the state) solves the dense KKT system
    /// with those controls as equality constraints.
    #[test]
    fn riccati_step_with_arcs_solves_the_constrained_dense_kkt_system() {
        let (n, h) = (9, 0.3);
        let (lin, mut r, e) = random_problem(n, h, 11);
        // Joint 0 on the limit at states 3..=5 (entry control 2, fixed 3, 4); joint 1 touches
        // it at state 7 (entry control 6 only).
        let mut maps = vec![ControlMap::default(); n];
        maps[2].entry[0] = true;
        maps[3].fixed[0] = true;
        maps[4].fixed[0] = true;
        maps[6].entry[1] = true;
        // The direct method zeroes the gradient of tied controls (the jumps absorb it).
        for (m, rk) in maps.iter().zip(r.iter_mut()) {
            for i in [0, 1] {
                if !m.free(i) {
                    rk[i] = 0.0;
                }
            }
        }
        let f = Factor::new(&lin, &r, h, 0.0, Some(&maps)).unwrap();
        let (du, nu) = f.solve(&lin, &e, true).unwrap();
        let (kkt, rhs, _) = dense(&lin, &r, &e, Some(&maps));
        let sol = kkt.clone().lu().solve(&rhs).unwrap();
        let nv = 2 * n;
        for k in 0..n {
            assert!(
                (du[k].x - sol[2 * k]).abs() < 1e-9,
                "du {k}: {} {}",
                du[k].x,
                sol[2 * k]
            );
            assert!((du[k].y - sol[2 * k + 1]).abs() < 1e-9, "du {k}");
        }
        for i in 0..5 {
            assert!((nu[i] - sol[nv + i]).abs() < 1e-9, "nu {i}");
        }
        assert_eq!(du[3].x, 0.0);
        assert_eq!(du[4].x, 0.0);
    }
}
