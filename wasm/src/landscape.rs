//! The landscapes the page offers: every built-in potential of the kernel
//! in two dimensions, picked by name at run time, and the potential on a
//! grid for the page's pictures (heat map, density, exact marginals).

use core::fmt;
use core::str::FromStr;

use hrla::{
    Ackley, DoubleWell, KnownMinimum, Levy, Potential, Quadratic, Rastrigin, StyblinskiTang,
};

/// A built-in potential of the kernel on `R^2`, chosen at run time.
///
/// Dispatching by `match` keeps one optimiser type for every landscape; the
/// arms call the kernel's own implementations, so a landscape's numbers are
/// the kernel's, bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Landscape {
    /// [`Rastrigin`], the paper's test function.
    Rastrigin,
    /// [`Ackley`].
    Ackley,
    /// [`Levy`].
    Levy,
    /// [`StyblinskiTang`].
    StyblinskiTang,
    /// [`DoubleWell`]: four global minima at `(±1, ±1)`.
    DoubleWell,
    /// [`Quadratic`] with stiffness 1 centred at the origin: its Gibbs law
    /// is the Gaussian `N(0, I / a)`.
    Quadratic(Quadratic<f64, 2>),
}

impl Landscape {
    /// Every landscape, in the order the page lists them.
    pub const NAMES: [&'static str; 6] = [
        "rastrigin",
        "ackley",
        "levy",
        "styblinski-tang",
        "double-well",
        "quadratic",
    ];

    /// The name the page and the address use.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Rastrigin => "rastrigin",
            Self::Ackley => "ackley",
            Self::Levy => "levy",
            Self::StyblinskiTang => "styblinski-tang",
            Self::DoubleWell => "double-well",
            Self::Quadratic(_) => "quadratic",
        }
    }

    /// `U` at each cell centre of an `nx` by `ny` grid over
    /// `[x0, x1] x [y0, y1]`, row by row from the top (`y1`) down, as the
    /// page's canvases are laid out.
    pub fn grid(&self, x0: f64, x1: f64, y0: f64, y1: f64, nx: usize, ny: usize) -> Vec<f64> {
        let mut out = Vec::with_capacity(nx * ny);
        let (dx, dy) = ((x1 - x0) / nx as f64, (y1 - y0) / ny as f64);
        for j in 0..ny {
            let y = y1 - (j as f64 + 0.5) * dy;
            for i in 0..nx {
                out.push(self.value(&[x0 + (i as f64 + 0.5) * dx, y]));
            }
        }
        out
    }
}

/// Why a landscape's name was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnknownLandscape;

impl fmt::Display for UnknownLandscape {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "`potential` must be one of {}",
            Landscape::NAMES.join(", ")
        )
    }
}

impl FromStr for Landscape {
    type Err = UnknownLandscape;

    fn from_str(name: &str) -> Result<Self, Self::Err> {
        Ok(match name {
            "rastrigin" => Self::Rastrigin,
            "ackley" => Self::Ackley,
            "levy" => Self::Levy,
            "styblinski-tang" => Self::StyblinskiTang,
            "double-well" => Self::DoubleWell,
            "quadratic" => {
                Self::Quadratic(Quadratic::new(1.0, [0.0, 0.0]).map_err(|_| UnknownLandscape)?)
            }
            _ => return Err(UnknownLandscape),
        })
    }
}

impl Potential<f64, 2> for Landscape {
    #[inline]
    fn value_and_gradient(&self, x: &[f64; 2], grad: &mut [f64; 2]) -> f64 {
        match self {
            Self::Rastrigin => Rastrigin.value_and_gradient(x, grad),
            Self::Ackley => Ackley.value_and_gradient(x, grad),
            Self::Levy => Levy.value_and_gradient(x, grad),
            Self::StyblinskiTang => StyblinskiTang.value_and_gradient(x, grad),
            Self::DoubleWell => DoubleWell.value_and_gradient(x, grad),
            Self::Quadratic(q) => q.value_and_gradient(x, grad),
        }
    }
}

impl KnownMinimum<f64, 2> for Landscape {
    fn global_minimum(&self) -> f64 {
        match self {
            Self::Rastrigin => KnownMinimum::<f64, 2>::global_minimum(&Rastrigin),
            Self::Ackley => KnownMinimum::<f64, 2>::global_minimum(&Ackley),
            Self::Levy => KnownMinimum::<f64, 2>::global_minimum(&Levy),
            Self::StyblinskiTang => KnownMinimum::<f64, 2>::global_minimum(&StyblinskiTang),
            Self::DoubleWell => KnownMinimum::<f64, 2>::global_minimum(&DoubleWell),
            Self::Quadratic(q) => q.global_minimum(),
        }
    }

    fn global_minimiser(&self) -> [f64; 2] {
        match self {
            Self::Rastrigin => Rastrigin.global_minimiser(),
            Self::Ackley => Ackley.global_minimiser(),
            Self::Levy => Levy.global_minimiser(),
            Self::StyblinskiTang => StyblinskiTang.global_minimiser(),
            Self::DoubleWell => DoubleWell.global_minimiser(),
            Self::Quadratic(q) => q.global_minimiser(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_minima_are_minima() {
        for name in Landscape::NAMES {
            let l: Landscape = name.parse().unwrap();
            assert_eq!(l.name(), name);
            let x = l.global_minimiser();
            let u = l.value(&x);
            assert!((u - l.global_minimum()).abs() < 1e-9, "{name}: U(x*) = {u}");
            // Nothing on a coarse grid around x* is lower.
            let g = l.grid(x[0] - 6.0, x[0] + 6.0, x[1] - 6.0, x[1] + 6.0, 61, 61);
            assert!(g.iter().all(|&v| v >= u - 1e-9), "{name}");
        }
        assert_eq!("sphere".parse::<Landscape>(), Err(UnknownLandscape));
    }

    #[test]
    fn the_grid_is_laid_out_from_the_top_left() {
        let g = Landscape::Quadratic(Quadratic::new(1.0, [0.0, 0.0]).unwrap())
            .grid(0.0, 4.0, 0.0, 2.0, 4, 2);
        // Cell centres x = 0.5, 1.5, 2.5, 3.5; y = 1.5 (first row), 0.5.
        assert_eq!(g[0], 0.5 * (0.25 + 2.25));
        assert_eq!(g[3], 0.5 * (12.25 + 2.25));
        assert_eq!(g[4], 0.5 * (0.25 + 0.25));
    }
}
