//! Commands of one link: COMMAND_LONG/INT decoded, executed by the vehicle, answered with one
//! COMMAND_ACK (and the requested message); PARAM_SET with its echo.

use super::*;

/// One COMMAND_LONG (or COMMAND_INT as one): duplicate check (information requests bypass the
/// cache and are answered every time: `duplicates::is_information_request`), decision, exactly
/// one ACK.
pub(super) fn handle_command(
    header: &MavHeader,
    cmd: &COMMAND_LONG_DATA,
    decision: CommandDecision,
    from: SocketAddr,
    sender: &Arc<Sender>,
    ctx: &LinkContext,
) {
    if decision == CommandDecision::NotForUs {
        return;
    }
    let key = CommandKey::new(header, cmd);
    let seen = sender
        .duplicates
        .lock()
        .map(|mut c| c.check(key, sender.wall_s()))
        .unwrap_or(Seen::New);
    let (header, command, s) = (*header, cmd.command, sender.clone());
    match seen {
        Seen::InProgress => {}
        Seen::Answered(result) => {
            tokio::spawn(async move { s.send(&command_ack(&header, command, result), from).await });
        }
        Seen::New => match decision {
            CommandDecision::NotForUs => {}
            CommandDecision::Unsupported => {
                tokio::spawn(async move {
                    answer(
                        &s,
                        key,
                        &header,
                        command,
                        AckOf::Result(MavResult::MAV_RESULT_UNSUPPORTED),
                        from,
                    )
                    .await
                });
            }
            CommandDecision::Refuse(outcome) => {
                tokio::spawn(async move { answer(&s, key, &header, command, AckOf::Outcome(&outcome), from).await });
            }
            CommandDecision::Reply(one_shot) => {
                let msg = match one_shot {
                    OneShot::AutopilotVersion => Some(autopilot_version(&ctx.identity)),
                    OneShot::Stream(stream) => message(stream, &ctx.snapshot.borrow()),
                };
                tokio::spawn(async move {
                    answer(
                        &s,
                        key,
                        &header,
                        command,
                        AckOf::Result(MavResult::MAV_RESULT_ACCEPTED),
                        from,
                    )
                    .await;
                    if let Some(msg) = msg {
                        s.send(&msg, from).await;
                    }
                });
            }
            CommandDecision::SetMessageInterval {
                message_id,
                interval_us,
            } => {
                let result = match sender
                    .streams
                    .lock()
                    .map(|mut t| t.set_interval(message_id, interval_us))
                {
                    Ok(Ok(())) => MavResult::MAV_RESULT_ACCEPTED,
                    _ => MavResult::MAV_RESULT_DENIED,
                };
                tokio::spawn(async move { answer(&s, key, &header, command, AckOf::Result(result), from).await });
            }
            CommandDecision::GetMessageInterval { message_id } => {
                let interval = sender.streams.lock().ok().and_then(|t| t.interval_us(message_id));
                tokio::spawn(async move {
                    match interval {
                        Some(interval_us) => {
                            answer(
                                &s,
                                key,
                                &header,
                                command,
                                AckOf::Result(MavResult::MAV_RESULT_ACCEPTED),
                                from,
                            )
                            .await;
                            let msg = MavMessage::MESSAGE_INTERVAL(MESSAGE_INTERVAL_DATA {
                                interval_us,
                                message_id: message_id as u16,
                            });
                            s.send(&msg, from).await;
                        }
                        None => {
                            answer(
                                &s,
                                key,
                                &header,
                                command,
                                AckOf::Result(MavResult::MAV_RESULT_DENIED),
                                from,
                            )
                            .await
                        }
                    }
                });
            }
            CommandDecision::Execute(request) => {
                let (tx, rx) = oneshot::channel();
                let queued = ctx.inbox.try_send(VehicleCommand::Request {
                    request,
                    reply: Some(tx),
                });
                tokio::spawn(async move {
                    let outcome = match queued {
                        Ok(()) => rx
                            .await
                            .unwrap_or(Outcome::TemporarilyRejected("Vehicle stopped".into())),
                        Err(_) => Outcome::TemporarilyRejected("Vehicle busy".into()),
                    };
                    answer(&s, key, &header, command, AckOf::Outcome(&outcome), from).await;
                });
            }
        },
    }
}

/// PARAM_SET: the vehicle applies it at the next tick; every peer of this link gets the
/// resulting PARAM_VALUE (the unchanged value when refused, with a STATUSTEXT saying why); an
/// unknown name gets PARAM_ERROR.
pub(super) fn set_param(
    name: String,
    value: f64,
    header: MavHeader,
    from: SocketAddr,
    sender: &Arc<Sender>,
    ctx: &LinkContext,
) {
    let (tx, rx) = oneshot::channel();
    let queued = ctx.inbox.try_send(VehicleCommand::SetParam {
        name: name.clone(),
        value,
        reply: tx,
    });
    let s = sender.clone();
    let mut params = ctx.params.clone();
    tokio::spawn(async move {
        let result = match queued {
            Ok(()) => rx.await.ok(),
            Err(_) => None,
        };
        let table = params.borrow_and_update().clone();
        let targets = s.targets.lock().map(|p| p.clone()).unwrap_or_default();
        match result {
            Some(Ok(index)) => {
                if let Some(msg) = param_value(&table, index) {
                    let mut to_all = targets;
                    if !to_all.contains(&from) {
                        to_all.push(from);
                    }
                    for to in to_all {
                        s.send(&msg, to).await;
                    }
                }
            }
            Some(Err(ParamError::Unknown(_))) => {
                s.send(&param_error_unknown(&header, &name), from).await;
                let text = format!("Unknown parameter {name}");
                s.send(&status_text(MavSeverity::MAV_SEVERITY_WARNING, &text), from)
                    .await;
            }
            refused => {
                if let Some(msg) = table.index_of(&name).and_then(|i| param_value(&table, i)) {
                    s.send(&msg, from).await;
                }
                let why = match refused {
                    Some(Err(e)) => e.to_string(),
                    _ => "Vehicle busy".to_string(),
                };
                s.send(&status_text(MavSeverity::MAV_SEVERITY_WARNING, &why), from)
                    .await;
            }
        }
    });
}

/// What an ACK reports.
enum AckOf<'a> {
    Result(MavResult),
    Outcome(&'a Outcome),
}

/// COMMAND_ACK to the sender (remembered for duplicates), and a STATUSTEXT with the reason of a refusal.
async fn answer(sender: &Sender, key: CommandKey, header: &MavHeader, command: MavCmd, ack: AckOf<'_>, to: SocketAddr) {
    let result = match &ack {
        AckOf::Result(r) => *r,
        AckOf::Outcome(o) => result_of(o),
    };
    if let Ok(mut cache) = sender.duplicates.lock() {
        cache.answered(key, result, sender.wall_s());
    }
    sender.send(&command_ack(header, command, result), to).await;
    if let AckOf::Outcome(
        Outcome::TemporarilyRejected(why) | Outcome::Denied(why) | Outcome::Unsupported(why) | Outcome::Failed(why),
    ) = ack
    {
        sender
            .send(&status_text(MavSeverity::MAV_SEVERITY_WARNING, why), to)
            .await;
    }
}
