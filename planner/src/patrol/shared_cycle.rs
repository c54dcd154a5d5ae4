//! The predictable baseline (patrolling issue, beyond the source): every UAV flies one closed
//! walk through all free cells, evenly spaced along it, one cell per cycle. On a grid without
//! blocked cells and with an even side the walk is a Hamiltonian cycle (a serpentine with a
//! return lane); otherwise it goes round a depth-first spanning tree, which passes each cell
//! once or more. Intervals between visits are as even as they can be, and turns few, but an
//! observer who saw one pass knows every next one.

use super::grid::CellGrid;
use super::simulate::{Log, Simulation};

/// A closed walk through every free cell reachable from `start`, as cells in flight order
/// (the last steps back to the first).
pub fn closed_walk(grid: &CellGrid, start: usize) -> Vec<usize> {
    let all_free = grid.free.iter().all(|&f| f);
    if all_free && grid.rows >= 2 && grid.cols >= 2 && start == 0 {
        if grid.rows.is_multiple_of(2) {
            return serpentine(grid, false);
        }
        if grid.cols.is_multiple_of(2) {
            return serpentine(grid, true);
        }
    }
    tree_tour(grid, start)
}

/// Rows out and back across columns 1.., then down column 0: a Hamiltonian cycle when the
/// number of rows is even (`transposed`: the same with rows and columns swapped).
fn serpentine(grid: &CellGrid, transposed: bool) -> Vec<usize> {
    let (lanes, span) = if transposed { (grid.cols, grid.rows) } else { (grid.rows, grid.cols) };
    let cell = |lane: usize, along: usize| if transposed { grid.index(lane, along) } else { grid.index(along, lane) };
    let mut walk = Vec::with_capacity(grid.len());
    for lane in 0..lanes {
        let along: Box<dyn Iterator<Item = usize>> = if lane.is_multiple_of(2) { Box::new(1..span) } else { Box::new((1..span).rev()) };
        if lane == 0 {
            walk.push(cell(0, 0));
        }
        walk.extend(along.map(|a| cell(lane, a)));
    }
    walk.extend((1..lanes).rev().map(|lane| cell(lane, 0)));
    walk
}

/// Round a depth-first spanning tree of the free cells from `start`: each cell entered, its
/// subtrees flown, then back to its parent.
fn tree_tour(grid: &CellGrid, start: usize) -> Vec<usize> {
    let mut seen = vec![false; grid.len()];
    let mut walk = vec![start];
    seen[start] = true;
    // (cell, next heading to try)
    let mut stack = vec![(start, 0usize)];
    while let Some(top) = stack.len().checked_sub(1) {
        let (cell, heading) = stack[top];
        if heading == 4 {
            stack.pop();
            if let Some(&(parent, _)) = stack.last() {
                walk.push(parent);
            }
            continue;
        }
        stack[top].1 += 1;
        if let Some(next) = grid.step(cell, heading)
            && !seen[next]
        {
            seen[next] = true;
            walk.push(next);
            stack.push((next, 0));
        }
    }
    if walk.len() > 1 {
        walk.pop(); // the tour ends where it began
    }
    walk
}

/// `uavs` UAVs evenly spaced on the closed walk from `start`, for `cycles` cycles.
pub fn simulate_shared_cycle(grid: &CellGrid, start: usize, uavs: usize, cycles: u32) -> Simulation {
    let walk = closed_walk(grid, start);
    let len = walk.len().max(1);
    let offsets: Vec<usize> = (0..uavs).map(|k| k * len / uavs.max(1)).collect();
    let mut log = Log::new(grid.len(), &offsets.iter().map(|&o| walk[o % len]).collect::<Vec<_>>());
    // each UAV starts heading along its first step: that step is no turn
    let step_heading = |i: usize| grid.heading(walk[i % len], walk[(i + 1) % len]);
    let mut headings: Vec<Option<usize>> = offsets.iter().map(|&o| step_heading(o)).collect();
    for t in 1..=cycles {
        for (k, &o) in offsets.iter().enumerate() {
            let i = (o + t as usize - 1) % len;
            let (here, next) = (walk[i], walk[(i + 1) % len]);
            let (Some(before), Some(h)) = (headings[k], step_heading(i)) else { continue }; // a one-cell walk
            log.moved(k, here, next, t, before, h);
            headings[k] = Some(h);
        }
    }
    let ends: Vec<usize> = offsets.iter().map(|&o| walk[(o + cycles as usize) % len]).collect();
    log.finish(&grid.free, &ends, cycles)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn is_closed_walk(grid: &CellGrid, walk: &[usize]) -> bool {
        walk.iter().zip(walk.iter().cycle().skip(1)).all(|(&a, &b)| (0..4).any(|h| grid.step(a, h) == Some(b)))
    }

    #[test]
    fn open_grids_with_an_even_side_get_a_hamiltonian_cycle_and_others_a_tree_tour() {
        for (cols, rows) in [(4, 4), (5, 4), (4, 5), (50, 50)] {
            let grid = CellGrid::open(cols, rows);
            let walk = closed_walk(&grid, 0);
            assert_eq!(walk.len(), cols * rows, "{cols}×{rows}");
            let mut cells = walk.clone();
            cells.sort_unstable();
            cells.dedup();
            assert_eq!(cells.len(), cols * rows);
            assert!(is_closed_walk(&grid, &walk), "{cols}×{rows}");
        }
        let mut holed = CellGrid::open(5, 5);
        holed.free[12] = false;
        let walk = closed_walk(&holed, 0);
        assert!(is_closed_walk(&holed, &walk));
        assert!((0..25).filter(|&c| holed.free[c]).all(|c| walk.contains(&c)) && !walk.contains(&12));
    }

    #[test]
    fn evenly_spaced_uavs_revisit_every_cell_at_the_same_interval() {
        let grid = CellGrid::open(10, 10);
        let run = simulate_shared_cycle(&grid, 0, 4, 1000);
        // 100 cells shared by 4 UAVs: every cell every 25 cycles once the walk is under way
        assert!(run.visits.iter().all(|&v| (39..=41).contains(&v)), "{:?}", run.visits);
        assert!(run.metrics.qmi < 26.0, "{}", run.metrics.qmi);
    }
}
