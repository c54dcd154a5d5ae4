//! Continuous-curvature turns (Fraichard and Scheuer 2004): a vehicle whose steering changes
//! the curvature at most `σ` per metre enters a circle of radius `r` along a clothoid of length
//! `1 / (r σ)`. Every such turn stays inside the circle through the clothoid's end point
//! centred on the arc's centre, of radius `R = √(x_c² + y_c²)`, where `(x_c, y_c)` is that
//! centre seen from the clothoid's start. Planning turns as Dubins paths of radius `R` keeps
//! the room a continuous-curvature turn needs (docs/methods.md, ground §3).

/// The radius of the circle bounding continuous-curvature turns of minimum radius `r` and
/// curvature rate `sigma` (1/m²).
pub fn cc_circle_radius(r: f64, sigma: f64) -> f64 {
    let kappa = 1.0 / r;
    let length = kappa / sigma;
    // the clothoid's end point by Simpson's rule on its heading θ(s) = σ s² / 2
    let steps = 200;
    let h = length / steps as f64;
    let (mut x, mut y) = (0.0, 0.0);
    for i in 0..=steps {
        let s = i as f64 * h;
        let w = if i == 0 || i == steps {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        let theta = sigma * s * s / 2.0;
        x += w * theta.cos();
        y += w * theta.sin();
    }
    let (x, y) = (x * h / 3.0, y * h / 3.0);
    let theta_end = kappa * length / 2.0;
    let (xc, yc) = (x - r * theta_end.sin(), y + r * theta_end.cos());
    xc.hypot(yc)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_circle_grows_as_the_steering_slows() {
        // a clothoid of length L moves the circle's centre out by about L² / (24 r)
        let (r, sigma) = (7.0, 0.02);
        let l = 1.0 / (r * sigma);
        let shift = l * l / (24.0 * r);
        let big = cc_circle_radius(r, sigma);
        // the centre lies about L/2 along and r + shift across
        assert!((big - (l / 2.0).hypot(r + shift)).abs() < 0.05, "{big}");
        assert!(cc_circle_radius(r, 0.05) < big);
        assert!((cc_circle_radius(r, 10.0) - r).abs() < 0.01);
    }
}
