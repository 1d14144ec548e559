//! `batch --memory`: the images painted at once stay within the budget, estimated from their
//! pixel counts. Four one-megapixel inputs (48 MB each by the estimate) over two workers: with a
//! budget for one they are painted one at a time, with a budget for two, two at a time.

mod common;

use anisopaint::batch::{self, Outcome};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

/// The most paintings that ran at the same time.
fn most_at_once(budget: u64) -> usize {
    let dir = tempfile::tempdir().unwrap();
    let items = common::header_only_items(dir.path(), "p", 4, (1000, 1000));
    let (running, most) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let outcomes = batch::run(
        &items,
        2,
        true,
        budget,
        |_| {
            let now = running.fetch_add(1, Ordering::SeqCst) + 1;
            most.fetch_max(now, Ordering::SeqCst);
            std::thread::sleep(Duration::from_millis(100));
            running.fetch_sub(1, Ordering::SeqCst);
            Ok(())
        },
        |_, _, _| {},
    );
    assert!(outcomes.iter().all(|o| *o == Outcome::Done), "{outcomes:?}");
    most.load(Ordering::SeqCst)
}

#[test]
fn paintings_at_once_stay_within_the_memory_budget() {
    let one = 1000 * 1000 * batch::BYTES_PER_PIXEL;
    assert_eq!(most_at_once(one + one / 2), 1);
    assert_eq!(most_at_once(3 * one), 2);
    // Smaller than one item: each runs alone rather than never.
    assert_eq!(most_at_once(one / 10), 1);
}

#[test]
fn memory_sizes_parse_as_users_write_them() {
    let gib = 1u64 << 30;
    assert_eq!(batch::parse_memory("2G").unwrap(), 2 * gib);
    assert_eq!(batch::parse_memory("1.5GiB").unwrap(), 3 * gib / 2);
    assert_eq!(batch::parse_memory("800m").unwrap(), 800 << 20);
    assert_eq!(batch::parse_memory("512KB").unwrap(), 512 << 10);
    assert_eq!(batch::parse_memory("3000000000").unwrap(), 3_000_000_000);
    for bad in ["", "G", "-1G", "2X", "lots", "0", "nanG", "1e30T"] {
        let e = batch::parse_memory(bad).unwrap_err().to_string();
        assert!(e.contains("--memory") && e.contains("800M"), "{bad}: {e}");
    }
}
