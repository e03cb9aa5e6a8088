use std::io::Write;
use std::time::Duration;

use super::*;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rotorpilot-logs-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn at(utc_s: u64) -> SystemTime {
    UNIX_EPOCH + Duration::from_secs(utc_s)
}

/// 2026-01-01 10:00:00 and 2026-01-02 11:30:00 UTC.
const FIRST: u32 = 1_767_261_600;
const SECOND: u32 = 1_767_353_400;

#[test]
fn logs_on_disk_are_listed_oldest_first_and_read_at_offsets() {
    let root = dir("list").join("log");
    let mut logs = LogDir::open(&root).unwrap();
    assert_eq!(logs.list().unwrap(), vec![], "a fresh directory has no logs");
    std::fs::create_dir_all(root.join("2026-01-02")).unwrap();
    std::fs::create_dir_all(root.join("2026-01-01")).unwrap();
    let bytes: Vec<u8> = (0..20_001u32).map(|i| (i * 7) as u8).collect();
    std::fs::write(root.join("2026-01-01/10_00_00.ulg"), &bytes).unwrap();
    std::fs::write(root.join("2026-01-02/11_30_00.ulg"), b"x").unwrap();
    // Not logs: other names, a stray file at the top, a directory named like a log.
    std::fs::write(root.join("2026-01-02/notes.txt"), b"keep").unwrap();
    std::fs::write(root.join("stray.ulg"), b"keep").unwrap();
    std::fs::create_dir_all(root.join("2026-01-02/12_00_00.ulg")).unwrap();
    assert_eq!(
        logs.list().unwrap(),
        vec![
            LogFile {
                utc_s: FIRST,
                size: 20_001
            },
            LogFile { utc_s: SECOND, size: 1 }
        ]
    );
    let mut buf = [0u8; 90];
    assert_eq!(logs.read_at(FIRST, 19_950, &mut buf), Ok(51));
    assert_eq!(&buf[..51], &bytes[19_950..]);
    assert_eq!(logs.read_at(FIRST, 90, &mut buf), Ok(90));
    assert_eq!(&buf[..], &bytes[90..180]);
    assert_eq!(logs.read_at(SECOND, 0, &mut buf), Ok(1));
    assert_eq!(logs.read_at(SECOND, 5, &mut buf), Ok(0));
    assert!(matches!(
        logs.read_at(FIRST + 1, 0, &mut buf),
        Err(LogStoreError::NotFound(_))
    ));
    let _ = std::fs::remove_dir_all(dir("list"));
}

#[test]
fn a_log_being_written_is_listed_growing_and_never_erased() {
    let root = dir("erase").join("log");
    let mut logs = LogDir::open(&root).unwrap();
    std::fs::create_dir_all(root.join("2026-01-01")).unwrap();
    std::fs::write(root.join("2026-01-01/10_00_00.ulg"), b"old").unwrap();
    std::fs::write(root.join("2026-01-01/notes.txt"), b"keep").unwrap();
    let writer = logs.clone();
    let mut new = writer.begin(at(u64::from(SECOND))).unwrap();
    assert_eq!(new.path, root.join("2026-01-02/11_30_00.ulg"));
    assert_eq!(
        (new.utc_s, logs.writing()),
        (SECOND, Some(SECOND)),
        "clones share the mark"
    );
    // A second arming within the same second takes the next one.
    let twin = writer.begin(at(u64::from(SECOND))).unwrap();
    assert_eq!(twin.utc_s, SECOND + 1);
    writer.end(twin.utc_s);
    assert_eq!(logs.writing(), None, "the last one begun was the one written");
    let mut new_again = writer.begin(at(u64::from(SECOND) + 60)).unwrap();
    new.file.write_all(b"ab").unwrap();
    new_again.file.write_all(&[1; 100]).unwrap();
    let sizes: Vec<_> = logs.list().unwrap().iter().map(|l| l.size).collect();
    assert_eq!(sizes, vec![3, 2, 0, 100]);
    logs.erase().unwrap();
    assert_eq!(
        logs.list().unwrap(),
        vec![LogFile {
            utc_s: SECOND + 60,
            size: 100
        }],
        "only the log being written stays"
    );
    assert!(!root.join("2026-01-01/10_00_00.ulg").exists());
    assert!(
        root.join("2026-01-01/notes.txt").exists(),
        "not a log: kept, and its directory too"
    );
    writer.end(new_again.utc_s);
    logs.erase().unwrap();
    assert_eq!(logs.list().unwrap(), vec![]);
    assert!(!root.join("2026-01-02").exists(), "an emptied date directory goes");
    assert!(writer.begin(UNIX_EPOCH - Duration::from_secs(1)).is_err());
    let _ = std::fs::remove_dir_all(dir("erase"));
}

#[test]
fn a_directory_not_made_yet_has_no_logs_until_the_first_one_makes_it() {
    let base = dir("lazy");
    let root = base.join("instance-0").join("log");
    let mut logs = LogDir::at(&root);
    assert!(!base.exists(), "nothing is created before a log begins");
    assert_eq!(logs.list().unwrap(), vec![]);
    logs.erase().unwrap();
    assert!(!base.exists(), "nor by an erase");
    let new = logs.begin(at(u64::from(FIRST))).unwrap();
    assert_eq!(new.path, root.join("2026-01-01/10_00_00.ulg"));
    assert_eq!(logs.list().unwrap(), vec![LogFile { utc_s: FIRST, size: 0 }]);
    let _ = std::fs::remove_dir_all(base);
}
