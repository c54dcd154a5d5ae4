//! The patrolling metrics of the spec §6, all lower-is-better: the quadratic mean of the
//! intervals between visits (QMI, seed 002 Eq. 1), the standard deviation of the visit counts
//! (SDF, Eq. 2) and the number of turning manoeuvres (NTM, Eq. 3).

use serde::Serialize;

/// Visits of every cell, kept as they happen.
#[derive(Debug, Clone)]
pub struct Visits {
    last: Vec<u32>,
    pub count: Vec<u32>,
    /// Σ of squared closed intervals per cell.
    squares: Vec<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct PatrolMetrics {
    /// Quadratic mean of the intervals between visits, open ones included (cycles).
    pub qmi: f64,
    /// Population standard deviation of the visit counts of the free cells.
    pub sdf: f64,
    /// Heading changes of all UAVs: a 90° change counts 1, a reversal 2.
    pub ntm: u64,
    /// Reversals among them.
    pub reversals: u64,
}

impl Visits {
    pub fn new(cells: usize) -> Visits {
        Visits { last: vec![0; cells], count: vec![0; cells], squares: vec![0.0; cells] }
    }

    pub fn visit(&mut self, cell: usize, t: u32) {
        let gap = f64::from(t - self.last[cell]);
        self.squares[cell] += gap * gap;
        self.last[cell] = t;
        self.count[cell] += 1;
    }

    /// The metrics at the end of `cycles` cycles, over the `free` cells.
    ///
    /// ```
    /// use coverplan_planner::patrol::Visits;
    /// // two cells over 10 cycles: one visited at 0 and 4, the other never
    /// let mut v = Visits::new(2);
    /// v.visit(0, 0);
    /// v.visit(0, 4);
    /// let m = v.metrics(&[true, true], 10, 0, 0);
    /// // intervals 0, 4, 6 and 10: sqrt((0 + 16 + 36 + 100) / 4)
    /// assert!((m.qmi - (152.0f64 / 4.0).sqrt()).abs() < 1e-12);
    /// assert!((m.sdf - 1.0).abs() < 1e-12);
    /// ```
    pub fn metrics(&self, free: &[bool], cycles: u32, ntm: u64, reversals: u64) -> PatrolMetrics {
        let cells: Vec<usize> = (0..free.len()).filter(|&c| free[c]).collect();
        let (mut squares, mut intervals) = (0.0, 0.0);
        for &c in &cells {
            let open = f64::from(cycles - self.last[c]);
            squares += self.squares[c] + open * open;
            intervals += f64::from(self.count[c]) + 1.0;
        }
        let n = cells.len().max(1) as f64;
        let mean = cells.iter().map(|&c| f64::from(self.count[c])).sum::<f64>() / n;
        let var = cells.iter().map(|&c| (f64::from(self.count[c]) - mean).powi(2)).sum::<f64>() / n;
        PatrolMetrics { qmi: (squares / intervals.max(1.0)).sqrt(), sdf: var.sqrt(), ntm, reversals }
    }
}
