use super::*;

/// A fresh folder under the system temp folder, removed by the test's end (best effort).
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tailor-files-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn reads_a_regular_file_under_its_limit_only() {
    let d = scratch("limit");
    let f = d.join("a.bin");
    fs::write(&f, [7u8; 100]).unwrap();
    assert_eq!(read_input(&f, 100).unwrap().len(), 100);
    let e = read_input(&f, 99).unwrap_err().to_string();
    assert!(e.contains("100 bytes is larger than the 99-byte limit"), "{e}");
}

#[test]
fn refuses_devices_folders_and_fifos_before_opening_them() {
    let e = read_input(Path::new("/dev/zero"), MAX_INPUT_BYTES).unwrap_err().to_string();
    assert!(e.contains("not a regular file"), "{e}");
    let d = scratch("kinds");
    let e = read_input(&d, MAX_INPUT_BYTES).unwrap_err().to_string();
    assert!(e.contains("is a folder"), "{e}");
    #[cfg(unix)]
    {
        let fifo = d.join("pipe");
        let ok = std::process::Command::new("mkfifo").arg(&fifo).status().map(|s| s.success()).unwrap_or(false);
        assert!(ok, "mkfifo is needed for this test");
        // Opening a FIFO with no writer blocks for ever: the check must come before the open.
        let e = read_input(&fifo, MAX_INPUT_BYTES).unwrap_err().to_string();
        assert!(e.contains("not a regular file"), "{e}");
    }
}

#[test]
fn a_sparse_file_over_the_limit_is_refused_without_reading_it() {
    let d = scratch("sparse");
    let f = d.join("big.bin");
    let file = File::create(&f).unwrap();
    file.set_len(3 << 30).unwrap(); // 3 GB, sparse: costs nothing on disk
    let t = std::time::Instant::now();
    let e = read_input(&f, MAX_INPUT_BYTES).unwrap_err().to_string();
    assert!(e.contains("larger than"), "{e}");
    assert!(t.elapsed().as_secs_f32() < 1.0);
}

#[test]
fn references_stay_in_their_files_folder() {
    let d = scratch("beside");
    let sub = d.join("scene");
    fs::create_dir_all(&sub).unwrap();
    let owner = sub.join("scene.gltf");
    fs::write(&owner, "{}").unwrap();
    fs::write(sub.join("mesh.bin"), [1u8, 2, 3]).unwrap();
    fs::write(sub.join("with space.bin"), [4u8]).unwrap();
    fs::write(d.join("secret.txt"), "secret").unwrap();
    assert_eq!(read_beside(&owner, "mesh.bin", "buffer 0", 10).unwrap(), vec![1, 2, 3]);
    assert_eq!(read_beside(&owner, "./mesh.bin", "buffer 0", 10).unwrap(), vec![1, 2, 3]);
    assert_eq!(read_beside(&owner, "with%20space.bin", "buffer 0", 10).unwrap(), vec![4]);
    for bad in ["../secret.txt", "%2E%2E/secret.txt", "/etc/passwd", "a/../../secret.txt", "", "%zz"] {
        let e = read_beside(&owner, bad, "buffer 0", 10).unwrap_err();
        assert!(matches!(e, TailorError::Parse { .. }), "{bad:?}: {e}");
        assert!(e.to_string().contains("buffer 0"), "{e}");
    }
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(d.join("secret.txt"), sub.join("out.bin")).unwrap();
        let e = read_beside(&owner, "out.bin", "buffer 0", 10).unwrap_err().to_string();
        assert!(e.contains("symbolic link out"), "{e}");
        std::os::unix::fs::symlink("/dev/zero", sub.join("zero.bin")).unwrap();
        assert!(read_beside(&owner, "zero.bin", "buffer 0", 10).is_err());
        // A link that stays inside the folder is just another name.
        std::os::unix::fs::symlink(sub.join("mesh.bin"), sub.join("alias.bin")).unwrap();
        assert_eq!(read_beside(&owner, "alias.bin", "buffer 0", 10).unwrap(), vec![1, 2, 3]);
    }
}

#[test]
fn outputs_never_overwrite_inputs_or_each_other() {
    let d = scratch("outputs");
    let input = d.join("p.svg");
    fs::write(&input, "<svg/>").unwrap();
    let report = d.join("report.json");
    // Fine: new files, also in folders that do not exist yet.
    check_outputs(&[("PATTERN", &input)], &[("-o", &d.join("g.json")), ("--report", &d.join("new/r.json"))]).unwrap();
    let e = check_outputs(&[("PATTERN", &input)], &[("-o", &input)]).unwrap_err().to_string();
    assert!(e.contains("-o: is PATTERN, an input of this run"), "{e}");
    // Another spelling of the same file is the same file.
    let other = d.join(".").join("p.svg");
    assert!(check_outputs(&[("PATTERN", &input)], &[("-o", &other)]).is_err());
    #[cfg(unix)]
    {
        fs::hard_link(&input, d.join("hard.svg")).unwrap();
        assert!(check_outputs(&[("PATTERN", &input)], &[("-o", &d.join("hard.svg"))]).is_err());
    }
    let e = check_outputs(&[], &[("--report", &report), ("-o", &report)]).unwrap_err().to_string();
    assert!(e.contains("is also --report"), "{e}");
    let e = check_outputs(&[], &[("-o", &d)]).unwrap_err().to_string();
    assert!(e.contains("is a folder"), "{e}");
    let e = check_outputs(&[], &[("-o", &input.join("x.json"))]).unwrap_err().to_string();
    assert!(e.contains("is not a folder"), "{e}");
    // No probe file is left behind.
    let left: Vec<_> = fs::read_dir(&d).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert!(left.iter().all(|n| !n.to_string_lossy().starts_with(".tailor-write-check")), "{left:?}");
}
