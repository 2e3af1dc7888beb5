//! The landscapes the page offers: every built-in potential of the kernel
//! in two dimensions, picked by name at run time, or a visitor's own
//! formula over a box; and the potential on a grid for the page's pictures
//! (heat map, density, exact marginals).

use core::fmt;
use core::str::FromStr;
use std::sync::Arc;

use crate::formula::{Formula, FormulaError};
use crate::num::Num;

use hrla::{KnownMinimum, Potential};
use hrla_dyn::{Builtin, BuiltinKind, BuiltinSpec, PointFunction, PotentialSpec};

pub use hrla_dyn::UnknownPotential as UnknownLandscape;

/// A potential on `R^2`, chosen at run time: one of the kernel's built-ins
/// (the run-time layer's list, [`BuiltinKind`]), by name, or a visitor's
/// formula.
///
/// Dispatching by `match` keeps one optimiser type for every landscape; the
/// built-ins are the kernel's own implementations, so a landscape's numbers
/// are the kernel's, bit for bit. A visitor's formula is the one landscape
/// that is not the kernel's: its own small interpreter, with an exact
/// gradient.
#[derive(Clone, Debug, PartialEq)]
pub enum Landscape {
    /// A built-in with its parameters by name (the quadratic: stiffness 1
    /// centred at the origin, whose Gibbs law is the Gaussian `N(0, I / a)`).
    Builtin(Builtin<2>),
    /// A visitor's formula over its box ([`Custom`]).
    Formula(Arc<Custom>),
}

/// A visitor's formula, with the box it is looked at over and its lowest
/// value there, which stands for the unknown `U*`.
#[derive(Clone, Debug, PartialEq)]
pub struct Custom {
    formula: Formula,
    bounds: [f64; 4],
    minimum: f64,
    minimiser: [f64; 2],
}

/// Grid points per axis of the search for a formula's lowest value.
const SEARCH_GRID: usize = 201;
/// Gradient steps that refine the lowest grid point.
const SEARCH_STEPS: usize = 200;

impl Custom {
    /// The formula as typed.
    pub fn text(&self) -> &str {
        self.formula.text()
    }

    /// The box `[x0, x1, y0, y1]`.
    pub fn bounds(&self) -> [f64; 4] {
        self.bounds
    }
}

impl Landscape {
    /// A visitor's formula over the box `[x0, x1, y0, y1]`. Its `U*` is not
    /// known: it is estimated as the lowest value on a 201 x 201 grid of the
    /// box, refined by gradient descent with backtracking within the box (a
    /// chain may find lower values, outside the box or between grid points
    /// in a narrow well). Errors: the formula's ([`CustomError::Formula`]), a box
    /// that is not finite and increasing ([`GridError`]), or a point of the
    /// grid where `U` or its gradient is not finite: the page could not draw
    /// it, and chains there would diverge.
    pub fn formula(text: &str, bounds: [f64; 4]) -> Result<Self, CustomError> {
        let formula = Formula::parse(text).map_err(CustomError::Formula)?;
        let [x0, x1, y0, y1] = bounds;
        if !(bounds.iter().all(|v| v.is_finite()) && x0 < x1 && y0 < y1) {
            return Err(GridError::Box(bounds).into());
        }
        if !((x1 - x0).is_finite() && (y1 - y0).is_finite()) {
            return Err(GridError::TooWide(bounds).into());
        }
        let n = SEARCH_GRID;
        let (dx, dy) = ((x1 - x0) / (n - 1) as f64, (y1 - y0) / (n - 1) as f64);
        let mut best = (f64::INFINITY, [x0, y0]);
        // Where U is not finite, and where only its gradient is not: the
        // first point and the extent of each, for a refusal that says where.
        let (mut bad_value, mut bad_gradient) = (Undefined::none(), Undefined::none());
        for j in 0..n {
            for i in 0..n {
                let x = [x0 + i as f64 * dx, y0 + j as f64 * dy];
                let (u, g) = formula.value_and_gradient(x[0], x[1]);
                if !u.is_finite() {
                    bad_value.add(x, u, g);
                } else if !g.iter().all(|v| v.is_finite()) {
                    bad_gradient.add(x, u, g);
                } else if u < best.0 {
                    best = (u, x);
                }
            }
        }
        for bad in [bad_value, bad_gradient] {
            if let Some(e) = bad.error() {
                return Err(e.into());
            }
        }
        let (minimum, minimiser) = descend(&formula, best, bounds);
        Ok(Self::Formula(Arc::new(Custom {
            formula,
            bounds,
            minimum,
            minimiser,
        })))
    }
}

/// The grid points of a formula's box where it is not finite: the first
/// one and the rectangle holding them all.
struct Undefined {
    first: Option<([f64; 2], f64, [f64; 2])>,
    region: [f64; 4],
}

impl Undefined {
    fn none() -> Self {
        Self {
            first: None,
            region: [
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ],
        }
    }

    fn add(&mut self, x: [f64; 2], value: f64, gradient: [f64; 2]) {
        self.first.get_or_insert((x, value, gradient));
        let r = &mut self.region;
        *r = [
            r[0].min(x[0]),
            r[1].max(x[0]),
            r[2].min(x[1]),
            r[3].max(x[1]),
        ];
    }

    fn error(&self) -> Option<GridError> {
        self.first
            .map(|(x, value, gradient)| GridError::FormulaNotFinite {
                x,
                value,
                gradient,
                region: self.region,
            })
    }
}

/// Gradient descent with backtracking from `start`, kept in the box: the
/// lowest value found and where.
fn descend(
    formula: &Formula,
    start: (f64, [f64; 2]),
    [x0, x1, y0, y1]: [f64; 4],
) -> (f64, [f64; 2]) {
    let (mut u, mut x) = start;
    let mut step = (x1 - x0).max(y1 - y0) * 1e-3;
    for _ in 0..SEARCH_STEPS {
        let (_, g) = formula.value_and_gradient(x[0], x[1]);
        let norm = g[0].hypot(g[1]);
        if !(norm > 0.0 && norm.is_finite()) {
            break;
        }
        let mut moved = false;
        while step > 1e-15 * (x1 - x0).max(y1 - y0) {
            let next = [
                (x[0] - step * g[0] / norm).clamp(x0, x1),
                (x[1] - step * g[1] / norm).clamp(y0, y1),
            ];
            let v = formula.value_and_gradient(next[0], next[1]).0;
            if v < u {
                (u, x) = (v, next);
                step *= 2.0;
                moved = true;
                break;
            }
            step /= 2.0;
        }
        if !moved {
            break;
        }
    }
    (u, x)
}

impl Landscape {
    /// Every built-in landscape, in the order the page lists them.
    pub const NAMES: [&'static str; BuiltinKind::ALL.len()] = BuiltinKind::NAMES;

    /// The built-in `kind`.
    pub fn named(kind: BuiltinKind) -> Self {
        Self::Builtin(Builtin::named(kind))
    }

    /// The potential as the run-time layer's settings take it.
    pub fn spec(&self) -> PotentialSpec {
        match self {
            Self::Builtin(b) => PotentialSpec::Builtin(BuiltinSpec::Named(b.kind())),
            Self::Formula(f) => PotentialSpec::Native(f.clone()),
        }
    }

    /// The name the page and the address use (`formula` for a visitor's).
    pub fn name(&self) -> &'static str {
        match self {
            Self::Formula(_) => "formula",
            Self::Builtin(b) => b.kind().name(),
        }
    }

    /// `U` at each cell centre of an `nx` by `ny` grid over
    /// `[x0, x1] x [y0, y1]`, row by row from the top (`y1`) down, as the
    /// page's canvases are laid out.
    ///
    /// Every value returned is finite. Refused, with nothing computed: a
    /// box that is not finite or not increasing, or so wide that its width
    /// overflows (the cell centres would be NaN), and a grid of no points
    /// or more than [`MAX_GRID`]. Refused on the way: a cell centre where
    /// `U` itself is not finite (it overflows far out, `x^4` in
    /// Styblinski-Tang beyond about `1e77`).
    pub fn grid(
        &self,
        x0: f64,
        x1: f64,
        y0: f64,
        y1: f64,
        nx: usize,
        ny: usize,
    ) -> Result<Vec<f64>, GridError> {
        cells([x0, x1, y0, y1], nx, ny, |x| {
            let u = self.value(&x);
            if u.is_finite() {
                Ok(u)
            } else {
                Err(GridError::NotFinite { x, value: u })
            }
        })
    }
}

/// A formula's `U` on a grid laid out as [`Landscape::grid`]'s, NaN where
/// it is not finite: the picture of a formula refused on its box, or seen
/// beyond it, shows where it is defined and where not. Refused: a formula
/// that cannot be read, and a grid [`Landscape::grid`] refuses for its
/// box or its points.
pub fn formula_picture(
    text: &str,
    bounds: [f64; 4],
    nx: usize,
    ny: usize,
) -> Result<Vec<f64>, CustomError> {
    let formula = Formula::parse(text).map_err(CustomError::Formula)?;
    Ok(cells(bounds, nx, ny, |x| {
        let u = formula.value_and_gradient(x[0], x[1]).0;
        Ok(if u.is_finite() { u } else { f64::NAN })
    })?)
}

/// `value` at each cell centre of an `nx` by `ny` grid over the box, row
/// by row from the top, after checking the box and the count.
fn cells(
    bounds: [f64; 4],
    nx: usize,
    ny: usize,
    mut value: impl FnMut([f64; 2]) -> Result<f64, GridError>,
) -> Result<Vec<f64>, GridError> {
    let [x0, x1, y0, y1] = bounds;
    if !(bounds.iter().all(|v| v.is_finite()) && x0 < x1 && y0 < y1) {
        return Err(GridError::Box(bounds));
    }
    let (width, height) = (x1 - x0, y1 - y0);
    if !(width.is_finite() && height.is_finite()) {
        return Err(GridError::TooWide(bounds));
    }
    if nx == 0 || ny == 0 || nx.saturating_mul(ny) > MAX_GRID {
        return Err(GridError::Points { nx, ny });
    }
    let mut out = Vec::with_capacity(nx * ny);
    let (dx, dy) = (width / nx as f64, height / ny as f64);
    for j in 0..ny {
        let y = y1 - (j as f64 + 0.5) * dy;
        for i in 0..nx {
            out.push(value([x0 + (i as f64 + 0.5) * dx, y])?);
        }
    }
    Ok(out)
}

/// The most grid points [`Landscape::grid`] computes at once (a 2048 x 2048
/// picture).
pub const MAX_GRID: usize = 1 << 22;

/// Why [`Landscape::formula`] made no landscape of a visitor's formula.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum CustomError {
    /// The formula cannot be read.
    Formula(FormulaError),
    /// Its box is not a box, or the formula is not finite on its grid.
    Grid(GridError),
}

impl fmt::Display for CustomError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Formula(e) => e.fmt(f),
            Self::Grid(e) => e.fmt(f),
        }
    }
}

impl core::error::Error for CustomError {}

impl From<GridError> for CustomError {
    fn from(e: GridError) -> Self {
        Self::Grid(e)
    }
}

/// Why [`Landscape::grid`] refused a grid.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum GridError {
    /// The box `[x0, x1, y0, y1]` is not finite, or not `x0 < x1` and
    /// `y0 < y1`.
    Box([f64; 4]),
    /// The box `[x0, x1, y0, y1]` is finite but its width or height
    /// overflows.
    TooWide([f64; 4]),
    /// No points, or more than [`MAX_GRID`].
    Points {
        /// Columns.
        nx: usize,
        /// Rows.
        ny: usize,
    },
    /// A visitor's formula, or only its gradient, is not finite at points
    /// of the grid its box is searched on: the chains follow the
    /// gradient, so both must be finite over the whole box.
    FormulaNotFinite {
        /// The first such point, row by row from `(x0, y0)`.
        x: [f64; 2],
        /// `U` there (finite when only the gradient is not).
        value: f64,
        /// The gradient there.
        gradient: [f64; 2],
        /// The smallest rectangle `[x0, x1, y0, y1]` holding every such
        /// point of the grid (of those where `U` is not finite, when there
        /// are any).
        region: [f64; 4],
    },
    /// `U` is not finite at a cell centre.
    NotFinite {
        /// The cell centre.
        x: [f64; 2],
        /// `U` there.
        value: f64,
    },
}

impl GridError {
    /// The argument at fault: `box`, or `nx` for the number of points.
    pub fn field(&self) -> &'static str {
        match self {
            Self::Points { .. } => "nx",
            _ => "box",
        }
    }
}

impl fmt::Display for GridError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = Num;
        match *self {
            Self::Box([x0, x1, y0, y1]) => write!(
                f,
                "the grid's `box` must be finite with x0 < x1 and y0 < y1, got [{}, {}] x [{}, {}]",
                n(x0),
                n(x1),
                n(y0),
                n(y1)
            ),
            Self::TooWide([x0, x1, y0, y1]) => write!(
                f,
                "the grid's `box` [{}, {}] x [{}, {}] is too wide: its width or height overflows",
                n(x0),
                n(x1),
                n(y0),
                n(y1)
            ),
            Self::Points { nx, ny } => write!(
                f,
                "the grid must have between 1 and {MAX_GRID} points, got `nx` x `ny` = {nx} x {ny}"
            ),
            Self::FormulaNotFinite {
                x,
                value,
                gradient,
                region,
            } => {
                let at = format!("({}, {})", n(x[0]), n(x[1]));
                let single = region[0] == region[1] && region[2] == region[3];
                // What the box must leave out: the one point, or the part
                // of the box where the grid found such points.
                let part = if single {
                    at.clone()
                } else {
                    // A line of such points (1/x) reads as the line.
                    let span = |name: &str, lo: f64, hi: f64| {
                        if lo == hi {
                            format!("{name} = {}", n(lo))
                        } else {
                            format!("{name} from {} to {}", n(lo), n(hi))
                        }
                    };
                    format!(
                        "the part with {} and {}",
                        span("x", region[0], region[1]),
                        span("y", region[2], region[3])
                    )
                };
                if value.is_finite() {
                    write!(
                        f,
                        "U = {} at {at} is finite, but its gradient is not ({}, {}), and the chains follow the gradient: \
                         move the box so that it leaves out {part}, or smooth the formula there \
                         (a kink such as sqrt(x^2 + y^2) is smooth as sqrt(x^2 + y^2 + 1e-6))",
                        n(value),
                        n(gradient[0]),
                        n(gradient[1])
                    )
                } else {
                    write!(
                        f,
                        "U = {} at {at}, and U must be finite over the whole box: move the box so that it leaves out {part} \
                         (a smaller box only helps where U overflows far out), or shift the formula so that it is \
                         defined there (1/(x^2 + y^2) is finite as 1/(x^2 + y^2 + 1e-6))",
                        n(value)
                    )
                }
            }
            Self::NotFinite { x, value } => write!(
                f,
                "U = {} at ({}, {}) in the grid's `box`: choose a box that leaves that point out",
                n(value),
                n(x[0]),
                n(x[1])
            ),
        }
    }
}

impl core::error::Error for GridError {}

impl FromStr for Landscape {
    type Err = UnknownLandscape;

    fn from_str(name: &str) -> Result<Self, Self::Err> {
        name.parse().map(Self::named)
    }
}

/// A formula is a function of the plane: the layer runs it in 2-D.
impl PointFunction for Custom {
    #[inline]
    fn value_and_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let (u, g) = self.formula.value_and_gradient(x[0], x[1]);
        grad.copy_from_slice(&g);
        u
    }

    fn dimension(&self) -> Option<usize> {
        Some(2)
    }
}

impl Potential<f64, 2> for Landscape {
    #[inline]
    fn value_and_gradient(&self, x: &[f64; 2], grad: &mut [f64; 2]) -> f64 {
        match self {
            Self::Builtin(b) => b.value_and_gradient(x, grad),
            Self::Formula(f) => {
                let (u, g) = f.formula.value_and_gradient(x[0], x[1]);
                *grad = g;
                u
            }
        }
    }
}

impl KnownMinimum<f64, 2> for Landscape {
    fn global_minimum(&self) -> f64 {
        match self {
            Self::Builtin(b) => b.global_minimum(),
            Self::Formula(f) => f.minimum,
        }
    }

    fn global_minimiser(&self) -> [f64; 2] {
        match self {
            Self::Builtin(b) => b.global_minimiser(),
            Self::Formula(f) => f.minimiser,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A formula of a built-in landscape is that landscape: values and
    /// gradients agree to rounding (the kernel's Rastrigin reduces its
    /// argument its own way), and the estimated U* is the true one.
    #[test]
    fn a_formula_is_the_potential_it_writes() {
        let typed = Landscape::formula(
            "2 + x^2 + y^2 - cos(2 pi x) - cos(2 pi y)",
            [-5.0, 5.0, -5.0, 5.0],
        )
        .unwrap();
        let built = Landscape::named(BuiltinKind::Rastrigin);
        for &x in &[[0.3, -1.7], [2.9, 3.1], [-4.4, 0.05]] {
            let (mut g1, mut g2) = ([0.0; 2], [0.0; 2]);
            let (u1, u2) = (
                typed.value_and_gradient(&x, &mut g1),
                built.value_and_gradient(&x, &mut g2),
            );
            assert!(
                (u1 - u2).abs() <= 1e-12 * (1.0 + u2.abs()),
                "{x:?}: {u1} {u2}"
            );
            for i in 0..2 {
                assert!(
                    (g1[i] - g2[i]).abs() <= 1e-11 * (1.0 + g2[i].abs()),
                    "{x:?}: {g1:?} {g2:?}"
                );
            }
        }
        assert!(
            typed.global_minimum().abs() < 1e-12,
            "{}",
            typed.global_minimum()
        );
        assert!(typed.global_minimiser().iter().all(|v| v.abs() < 1e-6));
        // Himmelblau's four global minima are 0; the search finds one.
        let h = Landscape::formula("(x^2 + y - 11)^2 + (x + y^2 - 7)^2", [-5.0, 5.0, -5.0, 5.0])
            .unwrap();
        assert!(
            h.global_minimum() < 1e-10 && h.global_minimum() >= 0.0,
            "{}",
            h.global_minimum()
        );
        assert_eq!(h.name(), "formula");
    }

    #[test]
    fn a_formula_that_cannot_be_drawn_on_its_box_is_refused() {
        let refusal = |text: &str| {
            let Err(CustomError::Grid(e @ GridError::FormulaNotFinite { .. })) =
                Landscape::formula(text, [-5.0, 5.0, -5.0, 5.0])
            else {
                panic!("{text} accepted");
            };
            e.to_string()
        };
        // U undefined on a half of the box: only moving the box helps.
        let log = refusal("log(x)");
        assert!(log.starts_with("U = NaN at (-5, -5), "), "{log}");
        assert!(
            log.contains("with x from -5 to 0 and y from -5 to 5"),
            "{log}"
        );
        assert!(log.contains("move the box"), "{log}");
        // U infinite at one point.
        let pole = refusal("1/(x^2 + y^2)");
        assert!(pole.starts_with("U = inf at (0, 0), "), "{pole}");
        assert!(pole.contains("leaves out (0, 0) "), "{pole}");
        assert!(pole.contains("1/(x^2 + y^2 + 1e-6)"), "{pole}");
        // U finite, its gradient not: said as such.
        let cone = refusal("sqrt(x^2 + y^2)");
        assert!(
            cone.starts_with("U = 0 at (0, 0) is finite, but its gradient is not"),
            "{cone}"
        );
        assert!(cone.contains("sqrt(x^2 + y^2 + 1e-6)"), "{cone}");
        assert!(Landscape::formula("sqrt(x^2 + y^2 + 1e-6)", [-5.0, 5.0, -5.0, 5.0]).is_ok());
        // Its picture is drawn where it is finite.
        let p = formula_picture("log(x)", [-1.0, 1.0, -1.0, 1.0], 4, 1).unwrap();
        assert!(p[0].is_nan() && p[1].is_nan());
        assert_eq!(p[3], 0.75f64.ln());
        assert!(Landscape::formula("log(x)", [0.5, 1.0, -1.0, 1.0]).is_ok());
        assert!(matches!(
            Landscape::formula("x", [1.0, -1.0, -1.0, 1.0]),
            Err(CustomError::Grid(GridError::Box(_)))
        ));
        assert!(matches!(
            Landscape::formula("x +", [-1.0, 1.0, -1.0, 1.0]),
            Err(CustomError::Formula(_))
        ));
        // Unbounded below: the estimate is the box's lowest, at its edge.
        let slope = Landscape::formula("x", [-1.0, 1.0, -1.0, 1.0]).unwrap();
        assert_eq!(slope.global_minimum(), -1.0);
    }

    #[test]
    fn names_round_trip_and_minima_are_minima() {
        for name in Landscape::NAMES {
            let l: Landscape = name.parse().unwrap();
            assert_eq!(l.name(), name);
            let x = l.global_minimiser();
            let u = l.value(&x);
            assert!((u - l.global_minimum()).abs() < 1e-9, "{name}: U(x*) = {u}");
            // Nothing on a coarse grid around x* is lower.
            let g = l
                .grid(x[0] - 6.0, x[0] + 6.0, x[1] - 6.0, x[1] + 6.0, 61, 61)
                .unwrap();
            assert!(g.iter().all(|&v| v >= u - 1e-9), "{name}");
        }
        assert_eq!("sphere".parse::<Landscape>(), Err(UnknownLandscape));
    }

    #[test]
    fn the_grid_is_laid_out_from_the_top_left() {
        let g = Landscape::named(BuiltinKind::Quadratic)
            .grid(0.0, 4.0, 0.0, 2.0, 4, 2)
            .unwrap();
        // Cell centres x = 0.5, 1.5, 2.5, 3.5; y = 1.5 (first row), 0.5.
        assert_eq!(g[0], 0.5 * (0.25 + 2.25));
        assert_eq!(g[3], 0.5 * (12.25 + 2.25));
        assert_eq!(g[4], 0.5 * (0.25 + 0.25));
    }

    /// Every value returned is finite; what cannot be is refused.
    #[test]
    fn a_grid_that_cannot_be_finite_is_refused() {
        let r = Landscape::named(BuiltinKind::Rastrigin);
        let m = f64::MAX;
        assert_eq!(
            r.grid(-1e308, 1e308, -1.0, 1.0, 4, 4),
            Err(GridError::TooWide([-1e308, 1e308, -1.0, 1.0]))
        );
        assert_eq!(
            r.grid(-1.0, 1.0, -m, m, 4, 4),
            Err(GridError::TooWide([-1.0, 1.0, -m, m]))
        );
        assert!(matches!(
            r.grid(-1e200, 1e200, -1.0, 1.0, 4, 4),
            Err(GridError::NotFinite { value, .. }) if value == f64::INFINITY
        ));
        assert!(matches!(
            r.grid(f64::NAN, 1.0, -1.0, 1.0, 4, 4),
            Err(GridError::Box(_))
        ));
        assert!(matches!(
            r.grid(1.0, 1.0, -1.0, 1.0, 4, 4),
            Err(GridError::Box(_))
        ));
        assert_eq!(
            r.grid(0.0, 1.0, 0.0, 1.0, 0, 4),
            Err(GridError::Points { nx: 0, ny: 4 })
        );
        assert_eq!(
            r.grid(0.0, 1.0, 0.0, 1.0, 4096, 4096),
            Err(GridError::Points { nx: 4096, ny: 4096 })
        );
        let far = r.grid(-m / 2.0, m / 2.0, -1e150, 1e150, 3, 3);
        assert!(matches!(far, Err(GridError::NotFinite { .. })));
        let g = r.grid(-1e150, 1e150, -1e150, 1e150, 9, 9).unwrap();
        assert!(g.iter().all(|u| u.is_finite()));
        assert_eq!(
            GridError::TooWide([-1e308, 1e308, -1.0, 1.0]).to_string(),
            "the grid's `box` [-1e308, 1e308] x [-1, 1] is too wide: its width or height overflows"
        );
    }
}
