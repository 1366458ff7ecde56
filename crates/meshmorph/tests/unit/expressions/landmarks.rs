use meshmorph::expressions::landmarks::*;

/// The recommended landmarks of the built-in template, by name, and
/// their positions on it.
fn template_landmarks() -> (Vec<String>, Vec<[f64; 3]>) {
    let t = meshmorph::expressions::template::ExpressionTemplate::arkit();
    RECOMMENDED
        .iter()
        .map(|&n| {
            let v = t.landmark(&n.to_string()).unwrap();
            (landmark_name(n), t.head.positions()[v as usize])
        })
        .unzip()
}

#[test]
fn swapped_sides_and_a_misplaced_landmark_are_refused_one_a_little_off_warned_about() {
    let (names, on_template) = template_landmarks();
    // A head: the template's landmarks turned, scaled, moved, and
    // given other proportions (wider by a tenth, a longer face).
    let head: Vec<[f64; 3]> = on_template
        .iter()
        .map(|p| [2.0 * p[2] + 1.0, 2.2 * p[1] - 3.0, -2.0 * 1.1 * p[0]])
        .collect();
    assert!(misplaced_landmarks(&on_template, &head, &names)
        .unwrap()
        .is_empty());
    // Left and right swapped: each point given the name of its mirror.
    let mirror = |name: &str| {
        if let Some(base) = name.strip_suffix("Left") {
            format!("{base}Right")
        } else if let Some(base) = name.strip_suffix("Right") {
            format!("{base}Left")
        } else {
            name.to_string()
        }
    };
    let swapped: Vec<[f64; 3]> = names
        .iter()
        .map(|n| head[names.iter().position(|m| *m == mirror(n)).unwrap_or(0)])
        .collect();
    let e = misplaced_landmarks(&on_template, &swapped, &names)
        .unwrap_err()
        .to_string();
    assert!(e.contains("left and right look swapped"), "{e}");
    // The lips' names swapped, or two eye corners'.
    for (a, b) in [
        ("upperLipTop", "lowerLipBottom"),
        ("eyeInnerLeft", "eyeOuterLeft"),
    ] {
        let (i, j) = (
            names.iter().position(|n| n == a).unwrap(),
            names.iter().position(|n| n == b).unwrap(),
        );
        let mut swapped = head.clone();
        swapped.swap(i, j);
        let e = misplaced_landmarks(&on_template, &swapped, &names)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("landmarks {a} and {b} look swapped")),
            "{e}"
        );
    }
    // One eye corner on the nose tip.
    let (corner, tip) = (
        names.iter().position(|n| n == "eyeOuterLeft").unwrap(),
        names.iter().position(|n| n == "noseTip").unwrap(),
    );
    let mut misplaced = head.clone();
    misplaced[corner] = head[tip];
    let e = misplaced_landmarks(&on_template, &misplaced, &names)
        .unwrap_err()
        .to_string();
    assert!(e.contains("eyeOuterLeft") && e.contains("leave"), "{e}");
    // Halfway there: named in a warning, not refused.
    misplaced[corner] = std::array::from_fn(|i| 0.3 * head[corner][i] + 0.7 * head[tip][i]);
    let w = misplaced_landmarks(&on_template, &misplaced, &names).unwrap();
    assert!(
        w.len() == 1 && w[0].contains("landmark eyeOuterLeft"),
        "{w:?}"
    );
}

#[test]
fn names_numbers_and_aliases_resolve() {
    assert_eq!(landmark_number("37"), Some(37));
    assert_eq!(landmark_number("ibug37"), Some(37));
    assert_eq!(landmark_number("eyeOuterRight"), Some(37));
    assert_eq!(landmark_number("NOSETIP"), Some(31));
    assert_eq!(landmark_number("69"), None);
    assert_eq!(landmark_number("0"), None);
    assert_eq!(landmark_number("elbow"), None);
    for &(alias, n) in ALIASES {
        assert_eq!(landmark_number(alias), Some(n));
        assert_eq!(landmark_name(n), alias);
    }
    // A point without an alias is named so that it reads back as one.
    assert_eq!(landmark_name(5), "ibug5");
    assert_eq!(landmark_number(&landmark_name(5)), Some(5));
    // Every alias names one point.
    let mut numbers: Vec<u8> = ALIASES.iter().map(|a| a.1).collect();
    numbers.sort_unstable();
    numbers.dedup();
    assert_eq!(numbers.len(), ALIASES.len());
}

#[test]
fn the_recommended_set_is_accepted_without_warnings() {
    assert_eq!(check_landmarks(&RECOMMENDED).unwrap(), Vec::<String>::new());
}

#[test]
fn too_few_are_refused_naming_what_is_missing() {
    let err = check_landmarks(&RECOMMENDED[..11]).unwrap_err().to_string();
    assert!(err.contains("11 landmarks given"), "{err}");
    for &n in &RECOMMENDED[11..] {
        assert!(err.contains(&landmark_name(n)), "{err}");
    }
    assert!(!err.contains("chin"), "{err}");
}

#[test]
fn repeated_landmarks_are_refused() {
    let mut n = RECOMMENDED.to_vec();
    n.push(31);
    assert!(check_landmarks(&n)
        .unwrap_err()
        .to_string()
        .contains("noseTip"));
}

#[test]
fn a_region_without_landmarks_is_warned_about() {
    let no_mouth: Vec<u8> = (1..=48).collect();
    let warnings = check_landmarks(&no_mouth).unwrap();
    assert_eq!(warnings.len(), 1);
    assert!(warnings[0].contains("the mouth"), "{warnings:?}");
}
