//! Symmetries of the swimmer: maps that take an extremal of one problem to an extremal of the
//! same cost of another (or the same) problem.
//!
//! - Reflection about the body's x-axis: `α → −α`, `(x, y, θ) → (x, −y, −θ)` (the connection
//!   satisfies `A(−α) = diag(1, −1, −1)·A(α)·(−I)`, so a reflected loop moves the body by the
//!   reflected displacement). It fixes `ᾱ = 0` only.
//! - With equal outer links, the half turn of the body that swaps front and rear:
//!   `(α1, α2) → (α2, α1)`, `(x, y, θ) → (−x, −y, θ)`. It fixes `ᾱ` with `ᾱ1 = ᾱ2`.
//! - Their composition: `(α1, α2) → (−α2, −α1)`, `(x, y, θ) → (−x, y, −θ)`; fixes `ᾱ1 = −ᾱ2`.
//!
//! Each acts linearly on shape velocities and on the coordinates `(α, x, y, θ)`, hence on the
//! multipliers of the direct method too (a signed permutation is its own inverse transpose).

use super::constraints::joint_limit::Limits;
use super::direct::Run;
use super::grid::Grid;
use crate::problem::Problem;
use nalgebra::{Vector2, Vector3, Vector5};
use purcell_core::Arc;

/// One symmetry, as signed permutations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Symmetry {
    /// Its name in reports.
    pub name: &'static str,
    /// `α → (s_0 α_{p_0}, s_1 α_{p_1})`.
    shape: ([usize; 2], [i8; 2]),
    /// `(x, y, θ) → (t_0 x, t_1 y, t_2 θ)`.
    target: [i8; 3],
}

const REFLECTION: Symmetry = Symmetry {
    name: "reflection about the x-axis",
    shape: ([0, 1], [-1, -1]),
    target: [1, -1, -1],
};
const SWAP: Symmetry = Symmetry {
    name: "front-rear swap",
    shape: ([1, 0], [1, 1]),
    target: [-1, -1, 1],
};
const BOTH: Symmetry = Symmetry {
    name: "front-rear swap and reflection",
    shape: ([1, 0], [-1, -1]),
    target: [-1, 1, -1],
};

impl Symmetry {
    /// The image of a shape (or shape velocity).
    pub fn shape(&self, a: &Vector2<f64>) -> Vector2<f64> {
        let ([p0, p1], [s0, s1]) = self.shape;
        Vector2::new(f64::from(s0) * a[p0], f64::from(s1) * a[p1])
    }

    /// The image of a control sequence (or shape path), step by step.
    pub fn controls(&self, u: &[Vector2<f64>]) -> Vec<Vector2<f64>> {
        u.iter().map(|v| self.shape(v)).collect()
    }

    /// The image of a target.
    pub fn target(&self, t: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(
            f64::from(self.target[0]) * t.x,
            f64::from(self.target[1]) * t.y,
            f64::from(self.target[2]) * t.z,
        )
    }

    /// The image of a coordinate vector `(α1, α2, x, y, θ)` (a state or a multiplier).
    pub fn coordinates(&self, v: &Vector5<f64>) -> Vector5<f64> {
        let a = self.shape(&Vector2::new(v[0], v[1]));
        let t = self.target(&Vector3::new(v[2], v[3], v[4]));
        Vector5::new(a.x, a.y, t.x, t.y, t.z)
    }

    /// The image of an arc of the joint limit: the image's joint `i` is `s_i α_{p_i}`, so an
    /// arc of joint `p_i` at `σ α_max` becomes one of joint `i` at `s_i σ α_max`.
    pub fn arc(&self, a: &Arc) -> Arc {
        let ([p0, _], [s0, s1]) = self.shape;
        let i = if p0 + 1 == usize::from(a.joint) { 0 } else { 1 };
        let s = [s0, s1][i];
        Arc::new(i as u8 + 1, s * a.sign, a.first, a.last)
    }

    /// The image of a run on `grid` of a problem this symmetry maps to itself
    /// ([`of_problem`]): the run of the image path, on `grid` with the image arcs. The
    /// discrete kinematics commute with the symmetry exactly (its target map is an
    /// automorphism of SE(2), its shape map preserves the connection's form), so the image of
    /// a converged extremal is one, of the same cost, certified again as any other.
    pub fn run(&self, grid: &Grid, run: &Run) -> (Grid, Run) {
        let limits = match &grid.limits {
            Limits::Arcs { alpha_max, arcs } => Limits::Arcs {
                alpha_max: *alpha_max,
                arcs: arcs.iter().map(|a| self.arc(a)).collect(),
            },
            other => other.clone(),
        };
        let image = run.image(|v| self.coordinates(v), |v| self.shape(v));
        (
            Grid {
                limits,
                ..grid.clone()
            },
            image,
        )
    }
}

/// The symmetries of `problem`'s swimmer that fix its start and end shapes (the target may
/// move).
pub fn of_swimmer(problem: &Problem) -> Vec<Symmetry> {
    let [_, l1, l2] = problem.swimmer.lengths();
    let mut out = Vec::new();
    let fixed = |f: &dyn Fn(&Vector2<f64>) -> bool| f(&problem.alpha0) && f(&problem.alpha_end);
    if fixed(&|a| *a == Vector2::zeros()) {
        out.push(REFLECTION);
    }
    if l1 == l2 && fixed(&|a| a.x == a.y) {
        out.push(SWAP);
    }
    if l1 == l2 && fixed(&|a| a.x == -a.y) {
        out.push(BOTH);
    }
    out
}

/// The symmetries that map `problem` to itself.
pub fn of_problem(problem: &Problem) -> Vec<Symmetry> {
    of_swimmer(problem)
        .into_iter()
        .filter(|s| s.target(&problem.target) == problem.target)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Spec;
    use crate::solver::grid::Grid;
    use crate::solver::stage::Rule;

    /// A loop and its image under each symmetry: the image's end is the image of the end.
    #[test]
    fn images_of_a_loop_move_the_body_by_the_image_of_its_displacement() {
        let p = Problem::new(&Spec::default()).unwrap();
        let grid = Grid::new(&p, 200, Rule::LEFT_POINT).unwrap();
        let u: Vec<Vector2<f64>> = (0..200)
            .map(|k| {
                let t = k as f64 / 200.0 * core::f64::consts::TAU;
                Vector2::new(0.9 * t.cos(), 0.5 * (2.0 * t).cos() + 0.2)
            })
            .collect();
        let end = *grid.rollout(&u).unwrap().last().unwrap();
        for s in of_swimmer(&p) {
            let image: Vec<_> = u.iter().map(|v| s.shape(v)).collect();
            let e = *grid.rollout(&image).unwrap().last().unwrap();
            assert!((e - s.coordinates(&end)).amax() < 1e-13, "{}", s.name);
        }
        assert_eq!(of_swimmer(&p).len(), 3);
    }

    /// An arc of the joint limit maps to the joint and side its states map to.
    #[test]
    fn an_arc_maps_to_the_joint_and_side_of_its_states_image() {
        let a = Arc::new(1, 1, 10, 20);
        for s in [REFLECTION, SWAP, BOTH] {
            let image = s.arc(&a);
            let on = s.shape(&Vector2::new(1.0, 0.0));
            let joint = if on.x != 0.0 { 0 } else { 1 };
            assert_eq!(usize::from(image.joint), joint + 1, "{}", s.name);
            assert_eq!(f64::from(image.sign), on[joint], "{}", s.name);
            assert_eq!((image.first, image.last), (10, 20));
            assert_eq!(s.arc(&image), a, "{}: an involution", s.name);
        }
    }
}
