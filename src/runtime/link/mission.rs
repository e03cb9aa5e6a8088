//! The mission protocol of one link against the vehicle's stored mission (mavlink.md §7).

use super::*;

/// The mission protocol (mavlink.md §7): uploads through `transfer`, downloads from the store;
/// an accepted upload replaces the vehicle's mission and the store.
pub(super) fn handle_mission(
    ids: Ids,
    step: MissionStep,
    from: SocketAddr,
    sender: &Arc<Sender>,
    ctx: &LinkContext,
    transfer: &mut MissionTransfer<SocketAddr>,
) {
    let send = |out: Vec<(SocketAddr, MavMessage)>| {
        let s = sender.clone();
        tokio::spawn(async move {
            for (to, msg) in out {
                s.send(&msg, to).await;
            }
        });
    };
    let stored = || ctx.mission_store.lock().map(|s| s.clone()).unwrap_or_default();
    let now = sender.wall_s();
    let (out, completed) = match step {
        MissionStep::Count(m) => transfer.on_count(from, ids, &m, now),
        MissionStep::Item(m) => transfer.on_item(from, &m, now),
        MissionStep::Clear => transfer.on_clear(from, ids),
        MissionStep::RequestList(t) => (vec![(from, download_count(ids, t, &stored()))], None),
        MissionStep::RequestItem { seq, mission_type } => {
            (vec![(from, download_item(ids, mission_type, seq, &stored()))], None)
        }
    };
    send(out);
    match completed {
        Some(Completed::Items(items)) => {
            let home = ctx.snapshot.borrow().home;
            let result = match parse_mission(&items, &home) {
                Ok(mission) => {
                    let queued = ctx.inbox.try_send(VehicleCommand::Request {
                        request: Request::SetMission(mission),
                        reply: None,
                    });
                    if queued.is_ok() {
                        if let Ok(mut store) = ctx.mission_store.lock() {
                            *store = items;
                        }
                        MavMissionResult::MAV_MISSION_ACCEPTED
                    } else {
                        MavMissionResult::MAV_MISSION_ERROR
                    }
                }
                Err(e) => {
                    let why = format!("Mission item {} refused: {:?}", e.seq, e.result);
                    send(vec![(from, status_text(MavSeverity::MAV_SEVERITY_WARNING, &why))]);
                    e.result
                }
            };
            send(transfer.finish(result));
        }
        Some(Completed::Cleared) => {
            let _ = ctx.inbox.try_send(VehicleCommand::Request {
                request: Request::SetMission(Mission::default()),
                reply: None,
            });
            if let Ok(mut store) = ctx.mission_store.lock() {
                store.clear();
            }
        }
        None => {}
    }
}
