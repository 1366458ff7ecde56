use meshmorph::expressions::arkit_names::*;

fn facekit_names() -> Vec<String> {
    let mut names: Vec<String> = ARKIT_NAMES
        .iter()
        .filter(|n| !matches!(**n, "tongueOut" | "browInnerUp" | "cheekPuff"))
        .map(|n| {
            n.strip_suffix("Left")
                .map(|b| format!("{b}_L"))
                .or_else(|| n.strip_suffix("Right").map(|b| format!("{b}_R")))
                .unwrap_or_else(|| n.to_string())
        })
        .collect();
    for extra in [
        "browInnerUp_L",
        "browInnerUp_R",
        "cheekPuff_L",
        "cheekPuff_R",
        "cheekRaiser_L",
        "PupilDilate_R",
    ] {
        names.push(extra.to_string());
    }
    names
}

#[test]
fn facekit_names_map_to_arkit_with_halves_joined_and_tongue_missing() {
    let names = facekit_names();
    let (recipes, missing) = arkit_recipes(&names, false);
    assert_eq!(missing, ["tongueOut"]);
    assert_eq!(recipes.len(), 51);
    let get = |n: &str| recipes.iter().find(|r| r.name == n).unwrap();
    assert_eq!(names[get("eyeBlinkLeft").sources[0]], "eyeBlink_L");
    assert_eq!(names[get("mouthSmileRight").sources[0]], "mouthSmile_R");
    let brow: Vec<&str> = get("browInnerUp")
        .sources
        .iter()
        .map(|&k| names[k].as_str())
        .collect();
    assert_eq!(brow, ["browInnerUp_L", "browInnerUp_R"]);
    assert_eq!(get("cheekPuff").sources.len(), 2);
    assert!(recipes.iter().all(|r| r.name != "cheekRaiser_L"));
}

#[test]
fn all_shapes_keeps_the_others_under_their_names() {
    let names = facekit_names();
    let (recipes, _) = arkit_recipes(&names, true);
    assert_eq!(recipes.len(), 53);
    assert_eq!(recipes[51].name, "cheekRaiser_L");
    assert_eq!(recipes[52].name, "PupilDilate_R");
}
