//! Watershed (patrolling spec §5.1, seed 002 Algorithm 6): the matrix read as a relief, its
//! valleys (cells below the mean) grouped into clusters of 8-connected cells; a UAV flies to a
//! random cell of the largest valley.

use super::grid::CellGrid;

/// The cells of the largest valley of `value` (cells below the floor of its mean over the free
/// cells), or `None` when there is none. `pick` chooses a start among the unclustered valley
/// cells (the source picks at random): it gets how many there are and returns an index.
pub fn largest_valley(grid: &CellGrid, value: &[f64], mut pick: impl FnMut(usize) -> usize) -> Option<Vec<usize>> {
    let free: Vec<usize> = (0..grid.len()).filter(|&c| grid.free[c]).collect();
    let threshold = (free.iter().map(|&c| value[c]).sum::<f64>() / free.len().max(1) as f64).floor();
    let mut clustered = vec![false; grid.len()];
    let mut best: Option<Vec<usize>> = None;
    loop {
        let open: Vec<usize> = free.iter().copied().filter(|&c| value[c] < threshold && !clustered[c]).collect();
        if open.is_empty() {
            return best;
        }
        let start = open[pick(open.len()).min(open.len() - 1)];
        let mut cluster = vec![start];
        clustered[start] = true;
        let mut k = 0;
        while k < cluster.len() {
            let (c, r) = grid.col_row(cluster[k]);
            k += 1;
            for dr in -1i64..=1 {
                for dc in -1i64..=1 {
                    let (nc, nr) = (c as i64 + dc, r as i64 + dr);
                    if nc < 0 || nr < 0 || nc >= grid.cols as i64 || nr >= grid.rows as i64 {
                        continue;
                    }
                    let n = grid.index(nc as usize, nr as usize);
                    if grid.free[n] && !clustered[n] && value[n] < threshold {
                        clustered[n] = true;
                        cluster.push(n);
                    }
                }
            }
        }
        if best.as_ref().is_none_or(|b| cluster.len() > b.len()) {
            best = Some(cluster);
        }
    }
}

/// A path from `from` to `to` over free cells, one cell per step, as an L along the axis of
/// `heading` first (the source's rule) when that L is clear, else a shortest path. Excludes
/// `from`; empty when `to` cannot be reached.
pub fn route(grid: &CellGrid, from: usize, to: usize, heading: usize) -> Vec<usize> {
    let ((c0, r0), (c1, r1)) = (grid.col_row(from), grid.col_row(to));
    let vertical_first = heading.is_multiple_of(2);
    let mut l = Vec::new();
    let (mut c, mut r) = (c0, r0);
    for leg in 0..2 {
        let vertical = (leg == 0) == vertical_first;
        while if vertical { r != r1 } else { c != c1 } {
            if vertical {
                r = if r1 > r { r + 1 } else { r - 1 };
            } else {
                c = if c1 > c { c + 1 } else { c - 1 };
            }
            l.push(grid.index(c, r));
        }
    }
    if l.iter().all(|&cell| grid.free[cell]) {
        return l;
    }
    // breadth first over the four headings
    let mut came = vec![usize::MAX; grid.len()];
    came[from] = from;
    let mut queue = std::collections::VecDeque::from([from]);
    while let Some(cell) = queue.pop_front() {
        if cell == to {
            let mut path = vec![to];
            while *path.last().expect("non-empty") != from {
                path.push(came[*path.last().expect("non-empty")]);
            }
            path.pop();
            path.reverse();
            return path;
        }
        for h in 0..4 {
            if let Some(n) = grid.step(cell, h)
                && came[n] == usize::MAX
            {
                came[n] = cell;
                queue.push_back(n);
            }
        }
    }
    Vec::new()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_largest_valley_is_found_and_routes_are_l_shaped_when_clear() {
        let grid = CellGrid::open(5, 5);
        // mean 1.2 → threshold 1: cells of value 0 are the valleys; two of them, sizes 3 and 1
        let mut value = vec![2.0; 25];
        for cell in [0, 1, 5, 24] {
            value[cell] = 0.0;
        }
        let valley = largest_valley(&grid, &value, |_| 0).unwrap();
        assert_eq!(valley.len(), 3);
        // heading north: along the column first
        let path = route(&grid, 0, grid.index(2, 3), 0);
        assert_eq!(path, vec![5, 10, 15, 16, 17]);
        let mut walled = grid.clone();
        walled.free[10] = false;
        let around = route(&walled, 0, grid.index(2, 3), 0);
        assert_eq!(around.len(), 5);
        assert!(around.iter().all(|&c| walled.free[c]) && *around.last().unwrap() == grid.index(2, 3));
    }
}
