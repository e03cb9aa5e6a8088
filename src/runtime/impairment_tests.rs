use super::*;

fn config(up: Impairment, down: Impairment) -> LinkImpairment {
    LinkImpairment {
        up,
        down,
        links: vec![LinkKind::Gcs, LinkKind::Api],
        seed: 7,
    }
}

#[test]
fn values_parse_per_direction_and_bad_ones_say_what_is_wrong() {
    assert_eq!(parse_probabilities("link-loss", "20%"), Ok((0.2, 0.2)));
    assert_eq!(parse_probabilities("link-loss", "0.05/30%"), Ok((0.05, 0.3)));
    assert_eq!(parse_delays("0..50ms"), Ok(((0.0, 0.05), (0.0, 0.05))));
    assert_eq!(parse_delays("20ms/0.1s"), Ok(((0.02, 0.02), (0.1, 0.1))));
    let e = parse_probabilities("link-loss", "20").unwrap_err();
    assert_eq!(
        e.to_string(),
        "--link-loss \"20\": a probability lies between 0% and 100%"
    );
    assert!(parse_probabilities("link-duplicate", "x%")
        .unwrap_err()
        .to_string()
        .contains("percentage"));
    assert!(parse_delays("50").unwrap_err().why.contains("unit"));
    assert!(parse_delays("50..10ms").unwrap_err().why.contains("shorter"));
    assert!(parse_delays("-1ms").is_err() && parse_delays("11s").is_err());
}

#[test]
fn loss_and_duplicates_come_at_their_rates_and_are_counted() {
    let spec = Impairment {
        loss: 0.2,
        duplicate: 0.05,
        delay_s: (0.0, 0.0),
    };
    let mut imp = Impairments::new(&config(spec, Impairment::default()), 0);
    let mut passed = 0;
    for k in 0..20_000u32 {
        passed += imp.offer(f64::from(k) * 1e-3, LinkKind::Gcs, true, k).len();
    }
    let c = imp.counts()[0].up;
    assert_eq!(c.datagrams, 20_000);
    assert!((c.dropped as f64 / 20_000.0 - 0.2).abs() < 0.01, "{c:?}");
    assert!((c.duplicated as f64 / 16_000.0 - 0.05).abs() < 0.01, "{c:?}");
    assert_eq!(passed as u64, c.datagrams - c.dropped + c.duplicated);
    assert_eq!(c.delayed, 0);
    // The other direction is untouched.
    assert_eq!(imp.offer(0.0, LinkKind::Gcs, false, 1), vec![1]);
    assert_eq!(imp.counts()[0].down.dropped, 0);
}

#[test]
fn delayed_datagrams_come_out_when_due_and_may_overtake_each_other() {
    let spec = Impairment {
        loss: 0.0,
        duplicate: 0.0,
        delay_s: (0.0, 0.05),
    };
    let mut imp = Impairments::new(&config(Impairment::default(), spec), 0);
    let mut out = Vec::new();
    for k in 0..100u32 {
        let t = f64::from(k) * 1e-3;
        out.extend(imp.offer(t, LinkKind::Api, false, k));
        out.extend(imp.due(t).1);
    }
    let mut t = 0.1;
    while let Some(next) = imp.next_due_s() {
        assert!(next <= 0.15 + 1e-9);
        t = next.max(t);
        out.extend(imp.due(t).1);
    }
    assert_eq!(out.len(), 100, "nothing lost");
    assert!(out.windows(2).any(|w| w[0] > w[1]), "some overtake");
    let mut sorted = out.clone();
    sorted.sort_unstable();
    assert_eq!(sorted, (0..100).collect::<Vec<_>>());
    assert!(imp.counts()[1].down.delayed > 90);
}

#[test]
fn the_same_seed_gives_the_same_fates_and_another_seed_others() {
    let spec = Impairment {
        loss: 0.3,
        duplicate: 0.1,
        delay_s: (0.0, 0.0),
    };
    let fates = |seed, vehicle| {
        let mut imp = Impairments::new(
            &LinkImpairment {
                seed,
                ..config(spec, spec)
            },
            vehicle,
        );
        (0..200u32)
            .map(|k| imp.offer(0.0, LinkKind::Gcs, true, k).len())
            .collect::<Vec<_>>()
    };
    assert_eq!(fates(1, 0), fates(1, 0));
    assert_ne!(fates(1, 0), fates(2, 0));
    assert_ne!(fates(1, 0), fates(1, 1), "each vehicle draws its own");
}

#[test]
fn a_link_not_impaired_passes_everything_uncounted() {
    let spec = Impairment {
        loss: 1.0,
        duplicate: 0.0,
        delay_s: (0.0, 0.0),
    };
    let mut imp = Impairments::new(
        &LinkImpairment {
            links: vec![LinkKind::Gcs],
            ..config(spec, spec)
        },
        0,
    );
    assert!(imp.offer(0.0, LinkKind::Gcs, true, 1).is_empty());
    assert_eq!(imp.offer(0.0, LinkKind::Api, true, 2), vec![2]);
    assert_eq!(imp.counts().len(), 1);
}
