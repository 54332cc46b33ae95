//! Work split in two, the second part on another thread (the machine this runs on has two
//! cores): each item is computed alone and the results are joined in order, so every result
//! is the one-thread result.

/// `(a(), b())`, `b` on another thread; a panic in it is raised again here.
pub(crate) fn both<A: Send, B: Send>(
    a: impl FnOnce() -> A + Send,
    b: impl FnOnce() -> B + Send,
) -> (A, B) {
    std::thread::scope(|scope| {
        let handle = scope.spawn(b);
        let first = a();
        let second = handle
            .join()
            .unwrap_or_else(|e| std::panic::resume_unwind(e));
        (first, second)
    })
}

/// `items.iter().filter_map(f)`, in order, the second half of `items` on another thread.
pub(crate) fn filter_map<T: Sync, U: Send>(
    items: &[T],
    f: impl Fn(&T) -> Option<U> + Sync,
) -> Vec<U> {
    let (low, high) = items.split_at(items.len() / 2);
    let run = |part: &[T]| part.iter().filter_map(&f).collect::<Vec<U>>();
    let (mut first, second) = both(|| run(low), || run(high));
    first.extend(second);
    first
}
