//! Turns to render, shared fairly between clients: at most `concurrent_renders` renders run at
//! once, and when a turn comes free it goes to the clients waiting in turn (round robin), each
//! client's own requests first come, first served. One client's backlog (fifty render jobs of
//! full-HD frames) then delays another client's small frame by one render at most, where a
//! single first-come queue made it wait for the whole backlog.
//!
//! A client is a connection ([`Client`]): the server has one token for everyone, so nothing
//! finer tells its clients apart. A client that opens many connections at once gets a share for
//! each; render jobs, the way to queue many frames, are all their creating connection's.

use std::collections::{BTreeMap, VecDeque};
use std::ops::Bound::{Excluded, Unbounded};
use std::sync::{Arc, Mutex};

use tokio::sync::oneshot;

/// Who asked for a render: the connection its request came on, numbered in the order the
/// server accepted them. Requests that came some other way (the router driven directly, as
/// tests do) are [`Client::ANY`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Client(pub u64);

impl Client {
    /// A request without a connection of its own.
    pub const ANY: Client = Client(0);
}

/// The turns and who waits for them.
pub(crate) struct Turns(Arc<Mutex<Queue>>);

#[derive(Default)]
struct Queue {
    /// Turns nobody holds.
    free: usize,
    /// Each waiting client's waiters, oldest first.
    waiting: BTreeMap<Client, VecDeque<oneshot::Sender<Turn>>>,
    /// The client served last: the next turn goes to the first waiting client after it.
    last: Option<Client>,
}

/// A turn to render: dropping it hands it to the next waiter, or frees it.
pub(crate) struct Turn(Option<Arc<Mutex<Queue>>>);

impl Turns {
    /// `count` turns (at least one).
    pub fn new(count: usize) -> Turns {
        Turns(Arc::new(Mutex::new(Queue { free: count.max(1), ..Queue::default() })))
    }

    /// Waits for a turn for `client`. Dropping the future before it is ready leaves the queue as
    /// if it had never waited (a turn handed to it meanwhile goes on to the next waiter).
    pub async fn take(&self, client: Client) -> Turn {
        let receiver = {
            let mut queue = lock(&self.0);
            if queue.free > 0 && queue.waiting.is_empty() {
                queue.free -= 1;
                // Served now, as a turn handed on would be: others waiting next go first.
                queue.last = Some(client);
                return Turn(Some(self.0.clone()));
            }
            let (sender, receiver) = oneshot::channel();
            queue.waiting.entry(client).or_default().push_back(sender);
            receiver
        };
        // A turn sent to a receiver dropped before it read it is dropped with it, and so goes
        // on to the next waiter.
        receiver.await.expect("a waiter's sender is dropped only by sending it a turn")
    }
}

impl Drop for Turn {
    fn drop(&mut self) {
        let Some(queue) = self.0.take() else { return };
        let mut next = lock(&queue);
        loop {
            // The first waiting client after the one served last, round the ring.
            let after = next.last;
            let client = match after.and_then(|last| next.waiting.range((Excluded(last), Unbounded)).next().map(|(c, _)| *c)) {
                Some(client) => client,
                None => match next.waiting.keys().next() {
                    Some(client) => *client,
                    None => {
                        next.free += 1;
                        return;
                    }
                },
            };
            let waiters = next.waiting.get_mut(&client).expect("a listed client waits");
            let sender = waiters.pop_front().expect("a listed client has a waiter");
            if waiters.is_empty() {
                next.waiting.remove(&client);
            }
            next.last = Some(client);
            // Sent, it is the waiter's turn (dropped unread, it comes back here); a waiter
            // that has gone gives it straight back.
            match sender.send(Turn(Some(queue.clone()))) {
                Ok(()) => return,
                Err(mut turn) => turn.0 = None,
            }
        }
    }
}

fn lock(queue: &Mutex<Queue>) -> std::sync::MutexGuard<'_, Queue> {
    queue.lock().unwrap_or_else(|e| e.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Who gets each turn, as `order` records it, when one turn goes round `waiters`.
    async fn served(waiters: &[u64]) -> Vec<u64> {
        let turns = Turns::new(1);
        let held = turns.take(Client(99)).await;
        let order = Arc::new(Mutex::new(Vec::new()));
        let mut tasks = Vec::new();
        for &client in waiters {
            let (turns, order) = (Turns(turns.0.clone()), order.clone());
            tasks.push(tokio::spawn(async move {
                let turn = turns.take(Client(client)).await;
                order.lock().unwrap().push(client);
                drop(turn);
            }));
            // Queued in this order.
            tokio::task::yield_now().await;
        }
        drop(held);
        for task in tasks {
            task.await.unwrap();
        }
        Arc::try_unwrap(order).unwrap().into_inner().unwrap()
    }

    /// One client's five requests and another's one: the other's goes second, not sixth.
    #[tokio::test]
    async fn turns_go_round_the_clients() {
        assert_eq!(served(&[1, 1, 1, 1, 1, 2]).await, [1, 2, 1, 1, 1, 1]);
        assert_eq!(served(&[3, 3, 2, 2, 1]).await, [1, 2, 3, 2, 3]);
        // The ring closes after the highest client number there can be.
        assert_eq!(served(&[u64::MAX, u64::MAX, 1]).await, [u64::MAX, 1, u64::MAX]);
    }

    /// A waiter that goes away neither holds a turn nor loses one: the next gets it.
    #[tokio::test]
    async fn a_waiter_that_goes_away_passes_its_turn_on() {
        let turns = Turns::new(1);
        let held = turns.take(Client(1)).await;
        let gone = tokio::spawn({
            let turns = Turns(turns.0.clone());
            async move { drop(turns.take(Client(2)).await) }
        });
        tokio::task::yield_now().await;
        gone.abort();
        let _ = gone.await;
        drop(held);
        let again = tokio::time::timeout(std::time::Duration::from_secs(1), turns.take(Client(3))).await;
        assert!(again.is_ok(), "the turn was lost with the waiter that went away");
        assert_eq!(lock(&turns.0).free, 0);
        drop(again);
        assert_eq!(lock(&turns.0).free, 1);
    }
}
