//! A batch survives a panicking item: the item fails with "internal error", its share of the
//! memory budget is given back, and every other item is painted. Every input claims a
//! 10000×10000 picture, more than the whole budget, so each item runs alone: had the panicking
//! item kept its share, the next one would wait for it for ever (the test would time out).

mod common;

use anisopaint::batch::{self, Outcome};
use std::sync::mpsc;
use std::time::Duration;

#[test]
fn a_panicking_item_fails_alone_and_gives_its_budget_back() {
    let dir = tempfile::tempdir().unwrap();
    let items = common::header_only_items(dir.path(), "big", 4, (10_000, 10_000));
    const { assert!(10_000u64 * 10_000 * batch::BYTES_PER_PIXEL > batch::MEMORY_BUDGET) };
    let (done, finished) = mpsc::channel();
    let run_items = items.clone();
    std::thread::spawn(move || {
        let outcomes = batch::run(
            &run_items,
            2,
            true,
            batch::MEMORY_BUDGET,
            |item| {
                if item.input.ends_with("big1.png") {
                    panic!("a bug in one painting");
                }
                std::fs::write(&item.output, b"painted")
                    .map_err(|e| anisopaint::Error::io(&item.output, e))
            },
            |_, _, _| {},
        );
        done.send(outcomes).unwrap();
    });
    let outcomes = finished
        .recv_timeout(Duration::from_secs(30))
        .expect("the batch finishes although one item panicked");
    assert_eq!(outcomes.len(), 4);
    for (k, outcome) in outcomes.iter().enumerate() {
        if k == 1 {
            let Outcome::Failed(why) = outcome else {
                panic!("item 1 must fail, got {outcome:?}")
            };
            assert!(
                why.starts_with("internal error: a bug in one painting"),
                "{why}"
            );
        } else {
            assert_eq!(*outcome, Outcome::Done, "item {k}");
            assert_eq!(std::fs::read(&items[k].output).unwrap(), b"painted");
        }
    }
    assert!(!items[1].output.exists());
}
