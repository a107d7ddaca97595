use super::*;
use crate::test_util::data_dir;

/// A minimal skinned GLB: a 2×1 quad strip bound to two joints (A at the origin, B at x = 1),
/// B rotating 0 → 90° about z over one second (LINEAR), A jumping to z = 5 at t = 0.75 (STEP).
fn two_joint_glb() -> Vec<u8> {
    glb_with_position_count(4)
}

fn glb_with_position_count(count: usize) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut push = |bytes: Vec<u8>| {
        views.push(format!(r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#, bin.len(), bytes.len()));
        bin.extend(bytes);
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
    };
    let f = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    push(f(&[0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 1.0, 0.0])); // 0 positions
    push([0u16, 1, 2, 0, 2, 3].iter().flat_map(|x| x.to_le_bytes()).collect()); // 1 indices
    push(vec![0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0]); // 2 joints (u8)
    push(f(&[1.0, 0.0, 0.0, 0.0].repeat(4))); // 3 weights
    let mut ibm = Mat4::IDENTITY.to_cols_array().to_vec();
    ibm.extend(Mat4::from_translation(Vec3::new(-1.0, 0.0, 0.0)).to_cols_array());
    push(f(&ibm)); // 4 inverse bind matrices
    push(f(&[0.0, 1.0])); // 5 rotation times
    let h = std::f32::consts::FRAC_1_SQRT_2;
    push(f(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, h, h])); // 6 rotations
    push(f(&[0.0, 0.75])); // 7 translation times
    push(f(&[0.0, 0.0, 0.0, 0.0, 0.0, 5.0])); // 8 translations
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
        "nodes":[{{"mesh":0,"skin":0}},{{"children":[2]}},{{"translation":[1,0,0]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"JOINTS_0":2,"WEIGHTS_0":3}},"indices":1}}]}}],
        "skins":[{{"joints":[1,2],"inverseBindMatrices":4}}],
        "animations":[{{"name":"bend","channels":[{{"sampler":0,"target":{{"node":2,"path":"rotation"}}}},
            {{"sampler":1,"target":{{"node":1,"path":"translation"}}}}],
          "samplers":[{{"input":5,"output":6}},{{"input":7,"output":8,"interpolation":"STEP"}}]}}],
        "accessors":[
          {{"bufferView":0,"componentType":5126,"count":{count},"type":"VEC3"}},
          {{"bufferView":1,"componentType":5123,"count":6,"type":"SCALAR"}},
          {{"bufferView":2,"componentType":5121,"count":4,"type":"VEC4"}},
          {{"bufferView":3,"componentType":5126,"count":4,"type":"VEC4"}},
          {{"bufferView":4,"componentType":5126,"count":2,"type":"MAT4"}},
          {{"bufferView":5,"componentType":5126,"count":2,"type":"SCALAR"}},
          {{"bufferView":6,"componentType":5126,"count":2,"type":"VEC4"}},
          {{"bufferView":7,"componentType":5126,"count":2,"type":"SCALAR"}},
          {{"bufferView":8,"componentType":5126,"count":2,"type":"VEC3"}}],
        "bufferViews":[{}],"buffers":[{{"byteLength":{}}}]}}"#,
        views.join(","),
        bin.len()
    );
    let mut j = json.into_bytes();
    while j.len() % 4 != 0 {
        j.push(b' ');
    }
    let mut glb = b"glTF".to_vec();
    glb.extend(2u32.to_le_bytes());
    glb.extend(((12 + 8 + j.len() + 8 + bin.len()) as u32).to_le_bytes());
    glb.extend((j.len() as u32).to_le_bytes());
    glb.extend(0x4E4F_534Au32.to_le_bytes());
    glb.extend(j);
    glb.extend((bin.len() as u32).to_le_bytes());
    glb.extend(0x004E_4942u32.to_le_bytes());
    glb.extend(bin);
    glb
}

fn close(a: [f32; 3], b: [f32; 3]) -> bool {
    (Vec3::from(a) - Vec3::from(b)).length() < 1e-5
}

#[test]
fn synthetic_skin_follows_its_joints() {
    let scene = GltfScene::from_glb(&two_joint_glb(), "strip.glb").unwrap();
    assert_eq!(scene.num_vertices(), 4);
    assert_eq!(scene.triangles(), &[[0, 1, 2], [0, 2, 3]]);
    assert_eq!(scene.animations()[0].name, "bend");
    assert_eq!(scene.animations()[0].duration, 1.0);
    let rest = scene.mesh_at(None, 0.0).unwrap();
    assert!(close(rest.positions[1], [2.0, 0.0, 0.0]) && close(rest.positions[2], [2.0, 1.0, 0.0]));
    let mut p = Vec::new();
    scene.positions_at(Some(0), 0.5, &mut p).unwrap();
    let h = std::f32::consts::FRAC_1_SQRT_2;
    assert!(close(p[0], [0.0, 0.0, 0.0]), "{:?}", p[0]);
    assert!(close(p[1], [1.0 + h, h, 0.0]), "{:?}", p[1]);
    scene.positions_at(Some(0), 1.0, &mut p).unwrap();
    assert!(close(p[1], [1.0, 1.0, 5.0]), "{:?}", p[1]);
    assert!(close(p[2], [0.0, 1.0, 5.0]), "{:?}", p[2]);
    assert!(close(p[3], [0.0, 1.0, 5.0]), "{:?}", p[3]);
    // Past the end: clamped to the last key.
    scene.positions_at(Some(0), 9.0, &mut p).unwrap();
    assert!(close(p[1], [1.0, 1.0, 5.0]));
    assert!(scene.positions_at(Some(3), 0.0, &mut p).is_err());
}

#[test]
fn malformed_glb_is_reported_not_panicked() {
    let glb = two_joint_glb();
    for cut in [3, 12, 20, 40, glb.len() / 2, glb.len() - 3] {
        let e = GltfScene::from_glb(&glb[..cut], "cut.glb").unwrap_err();
        assert!(e.to_string().starts_with("cut.glb"), "{e}");
    }
    // Random byte corruption: errors or a scene, never a panic.
    let mut rng = crate::test_util::Rng::new(17);
    for _ in 0..300 {
        let mut b = glb.clone();
        for _ in 0..1 + (rng.f32() * 4.0) as usize {
            let i = (rng.f32() * b.len() as f32) as usize % b.len();
            b[i] = (rng.next_u64() & 0xFF) as u8;
        }
        if let Ok(scene) = GltfScene::from_glb(&b, "fuzz.glb") {
            let mut p = Vec::new();
            let _ = scene.positions_at(Some(0), 0.3, &mut p);
        }
    }
    // Index past the vertex count.
    let e = GltfScene::from_glb(&glb_with_position_count(2), "bad.glb").unwrap_err();
    assert!(e.to_string().contains("out of range"), "{e}");
}

#[test]
fn cesium_man_animation_plays() {
    let Some(dir) = data_dir() else { return };
    let path = dir.join("bodies/khronos-cesiumman/CesiumMan.glb");
    if !path.exists() {
        return;
    }
    let scene = GltfScene::load(&path).unwrap();
    assert_eq!(scene.num_vertices(), 3273);
    assert_eq!(scene.triangles().len(), 4672);
    let anim = &scene.animations()[0];
    assert!(anim.duration > 0.5, "{}", anim.duration);
    let first = scene.mesh_at(Some(0), 0.0).unwrap();
    let mut max_moved = 0.0f32;
    for k in 0..=8 {
        let t = anim.duration * k as f32 / 8.0;
        let m = scene.mesh_at(Some(0), t).unwrap();
        let (lo, hi) = m.bounds().unwrap();
        let height = hi[1] - lo[1];
        assert!((1.35..1.65).contains(&height), "height {height} at t = {t}");
        for (a, b) in first.positions.iter().zip(&m.positions) {
            max_moved = max_moved.max((Vec3::from(*a) - Vec3::from(*b)).length());
        }
    }
    assert!(max_moved > 0.05, "the mesh barely moves: {max_moved} m");
}
