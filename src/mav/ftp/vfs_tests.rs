use super::*;

fn fs() -> Vfs {
    let mut fs = Vfs::new(100);
    fs.publish("/etc/extras/a.json", b"{}".to_vec()).unwrap();
    fs
}

#[test]
fn paths_normalise_and_parent_steps_are_refused() {
    assert_eq!(normalize("etc//extras/./a.json").unwrap(), "/etc/extras/a.json");
    assert_eq!(normalize("").unwrap(), "/");
    assert_eq!(normalize("/fs/microsd/../../etc"), Err(ErrorCode::FileProtected));
    assert!(writable("/fs/microsd/x") && writable("/fs/microsd/d/x"));
    assert!(!writable("/fs/microsd") && !writable("/fs/microsd/log") && !writable("/fs/microsd/log/a"));
    assert!(!writable("/etc/extras/a.json") && !writable("/fs/microsdx"));
}

#[test]
fn listings_show_published_files_and_implicit_directories() {
    let mut fs = fs();
    assert_eq!(
        fs.list("/").unwrap(),
        vec![Entry::Dir("etc".into()), Entry::Dir("fs".into())]
    );
    assert_eq!(fs.list("/etc/extras").unwrap(), vec![Entry::File("a.json".into(), 2)]);
    assert_eq!(fs.list("/fs/microsd/log").unwrap(), vec![], "the logs' mount point");
    assert_eq!(fs.list("/nope"), Err(ErrorCode::FileNotFound));
    assert_eq!(fs.list("/etc/extras/a.json"), Err(ErrorCode::FailErrno(ENOTDIR)));
    assert_eq!(fs.read("etc/extras/a.json").unwrap(), b"{}");
    assert_eq!(fs.read("/etc"), Err(ErrorCode::FileNotFound));
    assert_eq!(fs.crc32("/etc/extras/a.json"), Ok(crc32_part(b"{}", 0)));
    assert!(fs.publish("/fs/microsd/x", vec![]).is_err());
    assert!(fs.publish("/etc", vec![]).is_err());
    assert!(fs.publish("/fs/microsd/log/x.ulg", vec![]).is_err() && fs.publish("../x", vec![]).is_err());
}

#[test]
fn scratch_files_are_written_within_the_byte_limit() {
    let mut fs = fs();
    let p = fs.open_write("/fs/microsd/t.txt", true).unwrap();
    assert_eq!(fs.write(&p, 2, b"abc"), Ok(3));
    assert_eq!(fs.read(&p).unwrap(), b"\0\0abc");
    assert_eq!(fs.write(&p, 0, &[1; 200]), Err(ErrorCode::FailErrno(ENOSPC)));
    assert_eq!(fs.write(&p, u32::MAX as usize, b"x"), Err(ErrorCode::FailErrno(ENOSPC)));
    fs.truncate(&p, 1).unwrap();
    assert_eq!(fs.read(&p).unwrap(), b"\0");
    fs.open_write(&p, false).unwrap();
    assert_eq!(fs.read(&p).unwrap().len(), 1, "OpenFileWO keeps the bytes");
    assert_eq!(
        fs.open_write("/fs/microsd/no/dir.txt", true),
        Err(ErrorCode::FileNotFound)
    );
    assert_eq!(fs.open_write("/etc/extras/a.json", true), Err(ErrorCode::FileProtected));
    assert_eq!(fs.open_write("/fs/microsd/log/x", true), Err(ErrorCode::FileProtected));
    assert_eq!(fs.remove_file("/etc/extras/a.json"), Err(ErrorCode::FileProtected));
    assert_eq!(fs.scratch_used(), 1);
    fs.remove_file(&p).unwrap();
    assert_eq!(fs.remove_file(&p), Err(ErrorCode::FileNotFound));
}

#[test]
fn directories_are_made_renamed_and_removed_when_empty() {
    let mut fs = fs();
    fs.create_dir("/fs/microsd/d").unwrap();
    assert_eq!(fs.create_dir("/fs/microsd/d"), Err(ErrorCode::FileExists));
    assert_eq!(fs.create_dir("/fs/microsd/x/y"), Err(ErrorCode::FileNotFound));
    let f = fs.open_write("/fs/microsd/d/f", true).unwrap();
    fs.write(&f, 0, b"hi").unwrap();
    assert_eq!(fs.remove_dir("/fs/microsd/d"), Err(ErrorCode::FailErrno(ENOTEMPTY)));
    fs.rename("/fs/microsd/d", "/fs/microsd/e").unwrap();
    assert_eq!(fs.read("/fs/microsd/e/f").unwrap(), b"hi");
    assert!(!fs.is_dir("/fs/microsd/d"));
    fs.rename("/fs/microsd/e/f", "/fs/microsd/g").unwrap();
    assert_eq!(
        fs.rename("/fs/microsd/e", "/fs/microsd/e/h"),
        Err(ErrorCode::FailErrno(EINVAL))
    );
    assert_eq!(
        fs.rename("/fs/microsd/g", "/fs/microsd/e"),
        Err(ErrorCode::FailErrno(EISDIR))
    );
    assert_eq!(
        fs.rename("/etc/extras/a.json", "/fs/microsd/a"),
        Err(ErrorCode::FileProtected)
    );
    fs.remove_dir("/fs/microsd/e").unwrap();
    assert_eq!(fs.remove_dir("/fs/microsd/e"), Err(ErrorCode::FileNotFound));
    assert_eq!(fs.remove_dir("/fs/microsd/log"), Err(ErrorCode::FileProtected));
    assert_eq!(
        fs.list("/fs/microsd").unwrap(),
        vec![Entry::File("g".into(), 2), Entry::Dir("log".into())]
    );
}

#[test]
fn scratch_entries_and_their_names_are_bounded_too() {
    // Empty files and directories cost no file bytes, but each is an entry with a path.
    let mut fs = Vfs::new(100).with_entry_limits(3, 60);
    fs.create_dir("/fs/microsd/a").unwrap();
    fs.open_write("/fs/microsd/a/f", true).unwrap();
    fs.open_write("/fs/microsd/g", true).unwrap();
    assert_eq!(fs.scratch_entries(), (3, 13 + 15 + 13));
    let full = Err(ErrorCode::FailErrno(ENOSPC));
    assert_eq!(fs.create_dir("/fs/microsd/b"), full, "a fourth entry");
    assert_eq!(fs.open_write("/fs/microsd/h", true).map(|_| ()), full);
    // Opening one that exists costs nothing.
    assert!(fs.open_write("/fs/microsd/g", false).is_ok());
    // Renaming to a longer name costs its extra bytes per entry moved (the directory and its file).
    assert_eq!(fs.rename("/fs/microsd/a", "/fs/microsd/abcdefghijk"), full);
    fs.rename("/fs/microsd/a", "/fs/microsd/abcdefghij").unwrap();
    assert_eq!(fs.scratch_entries(), (3, 59));
    // Freeing an entry makes room again.
    fs.remove_file("/fs/microsd/g").unwrap();
    fs.create_dir("/fs/microsd/b").unwrap();
    // By name bytes alone.
    let mut fs = Vfs::new(100).with_entry_limits(100, 30);
    fs.create_dir("/fs/microsd/0123456789").unwrap();
    assert_eq!(fs.create_dir("/fs/microsd/01"), full);
}

#[test]
fn the_default_scratch_area_holds_a_bounded_number_of_entries() {
    let mut fs = Vfs::default();
    let name = "x".repeat(200);
    let mut made = 0;
    for k in 0..20_000 {
        if fs.create_dir(&format!("/fs/microsd/{k}{name}")).is_err() {
            break;
        }
        made += 1;
    }
    let (n, bytes) = fs.scratch_entries();
    assert_eq!(n, made);
    assert!(
        made < SCRATCH_ENTRY_LIMIT && bytes <= SCRATCH_NAME_LIMIT_BYTES,
        "{made} {bytes}"
    );
    assert!(made > 200, "{made}");
}
