use super::*;
use crate::mav::logs::MemLogStore;

/// Three logs: 200, 3 and 180 bytes (times 100, 200, 300).
fn store() -> MemLogStore {
    let mut store = MemLogStore::default();
    store.insert(300, vec![3; 180]);
    store.insert(100, (0..200u32).map(|i| i as u8).collect());
    store.insert(200, vec![2; 3]);
    store
}

fn drain(server: &mut LogServer, store: &mut MemLogStore) -> Vec<MavMessage> {
    std::iter::from_fn(|| server.next_message(store)).collect()
}

fn entries(messages: &[MavMessage]) -> Vec<(u16, u16, u16, u32, u32)> {
    messages
        .iter()
        .map(|m| match m {
            MavMessage::LOG_ENTRY(e) => (e.id, e.num_logs, e.last_log_num, e.size, e.time_utc),
            other => panic!("not a LOG_ENTRY: {other:?}"),
        })
        .collect()
}

fn data(messages: &[MavMessage]) -> Vec<(u16, u32, u8)> {
    messages
        .iter()
        .map(|m| match m {
            MavMessage::LOG_DATA(d) => (d.id, d.ofs, d.count),
            other => panic!("not a LOG_DATA: {other:?}"),
        })
        .collect()
}

/// LOG_REQUEST_DATA of `count` bytes of log `id` from `offset`.
fn request(id: u16, offset: u32, count: u32) -> LogRequest {
    LogRequest::Data { id, offset, count }
}

#[test]
fn the_list_numbers_logs_oldest_first_and_honours_the_range() {
    let (mut store, mut s) = (store(), LogServer::default());
    s.handle(&mut store, LogRequest::List { start: 0, end: 0xFFFF });
    assert_eq!(
        entries(&drain(&mut s, &mut store)),
        vec![(0, 3, 2, 200, 100), (1, 3, 2, 3, 200), (2, 3, 2, 180, 300)]
    );
    assert!(!s.busy());
    s.handle(&mut store, LogRequest::List { start: 1, end: 1 });
    assert_eq!(entries(&drain(&mut s, &mut store)), vec![(1, 3, 1, 3, 200)]);
    // Past the last id: clamped to it, as PX4 clamps.
    s.handle(&mut store, LogRequest::List { start: 7, end: 9 });
    assert_eq!(entries(&drain(&mut s, &mut store)), vec![(2, 3, 2, 180, 300)]);
    s.handle(&mut store, LogRequest::List { start: 2, end: 1 });
    assert!(drain(&mut s, &mut store).is_empty(), "an empty range lists nothing");
}

#[test]
fn an_empty_store_lists_one_entry_without_logs() {
    let (mut store, mut s) = (MemLogStore::default(), LogServer::default());
    s.handle(&mut store, LogRequest::List { start: 0, end: 0xFFFF });
    assert_eq!(entries(&drain(&mut s, &mut store)), vec![(0, 0, 0, 0, 0)]);
    s.handle(&mut store, request(0, 0, 90));
    assert!(drain(&mut s, &mut store).is_empty());
}

#[test]
fn a_re_request_keeps_the_snapshot_and_a_new_list_takes_another() {
    let (mut store, mut s) = (store(), LogServer::default());
    s.handle(&mut store, LogRequest::List { start: 0, end: 0xFFFF });
    drain(&mut s, &mut store);
    store.insert(50, vec![9; 10]);
    s.handle(&mut store, LogRequest::List { start: 1, end: 2 });
    assert_eq!(
        entries(&drain(&mut s, &mut store))[0],
        (1, 3, 2, 3, 200),
        "ids stay put"
    );
    s.handle(&mut store, LogRequest::List { start: 0, end: 0 });
    assert_eq!(entries(&drain(&mut s, &mut store)), vec![(0, 4, 0, 10, 50)]);
}

#[test]
fn data_comes_in_90_byte_pieces_to_the_count_asked() {
    let (mut store, mut s) = (store(), LogServer::default());
    s.handle(&mut store, request(0, 0, 200));
    assert!(drain(&mut s, &mut store).is_empty(), "nothing before a list");
    s.handle(&mut store, LogRequest::List { start: 0, end: 0xFFFF });
    drain(&mut s, &mut store);
    s.handle(&mut store, request(0, 0, u32::MAX));
    let out = drain(&mut s, &mut store);
    assert_eq!(data(&out), vec![(0, 0, 90), (0, 90, 90), (0, 180, 20)]);
    let MavMessage::LOG_DATA(last) = &out[2] else { panic!() };
    assert_eq!(
        &last.data[..20],
        &(180..200u32).map(|i| i as u8).collect::<Vec<_>>()[..]
    );
    // A resume from an offset, and a count that ends mid-piece.
    s.handle(&mut store, request(0, 45, 100));
    assert_eq!(data(&drain(&mut s, &mut store)), vec![(0, 45, 90), (0, 135, 10)]);
    // A size that is a multiple of 90 ends on a full piece; asking at the end gets the empty one.
    s.handle(&mut store, request(2, 0, u32::MAX));
    assert_eq!(data(&drain(&mut s, &mut store)), vec![(2, 0, 90), (2, 90, 90)]);
    s.handle(&mut store, request(2, 180, u32::MAX));
    assert_eq!(data(&drain(&mut s, &mut store)), vec![(2, 180, 0)]);
    s.handle(&mut store, request(2, 5000, 90));
    assert_eq!(data(&drain(&mut s, &mut store)), vec![(2, 5000, 0)]);
    s.handle(&mut store, request(3, 0, 90));
    assert!(drain(&mut s, &mut store).is_empty(), "no such id: nothing");
}

#[test]
fn a_new_request_end_or_forget_stops_the_transfer() {
    let (mut store, mut s) = (store(), LogServer::default());
    s.handle(&mut store, LogRequest::List { start: 0, end: 0xFFFF });
    drain(&mut s, &mut store);
    s.handle(&mut store, request(0, 0, 200));
    assert_eq!(data(&[s.next_message(&mut store).unwrap()]), vec![(0, 0, 90)]);
    s.handle(&mut store, request(1, 0, 200));
    assert_eq!(data(&drain(&mut s, &mut store)), vec![(1, 0, 3)]);
    s.handle(&mut store, request(0, 0, 200));
    s.next_message(&mut store);
    s.handle(&mut store, LogRequest::End);
    assert!(!s.busy() && drain(&mut s, &mut store).is_empty());
    // After END the list still holds: the next log downloads without listing again.
    s.handle(&mut store, request(1, 1, 200));
    assert_eq!(data(&drain(&mut s, &mut store)), vec![(1, 1, 2)]);
    s.forget();
    s.handle(&mut store, request(1, 0, 200));
    assert!(drain(&mut s, &mut store).is_empty(), "erased: list again first");
}

#[test]
fn a_log_being_written_is_served_as_listed() {
    let (mut store, mut s) = (store(), LogServer::default());
    s.handle(&mut store, LogRequest::List { start: 0, end: 0xFFFF });
    drain(&mut s, &mut store);
    store.insert(200, vec![2; 500]);
    s.handle(&mut store, request(1, 0, u32::MAX));
    assert_eq!(data(&drain(&mut s, &mut store)), vec![(1, 0, 3)]);
}
