//! The course program: byte-exact against the course's expected output and hand-derived cases.

use crate::support::{ok_stdout, run, shared, write};

#[test]
fn normal_txt_at_t20_matches_the_course_output_byte_for_byte() {
    let input = shared!("assignment/normal.txt");
    let expected = std::fs::read_to_string(shared!("assignment/normal_T20_expected.txt")).unwrap();
    let out = run("particles", &[input.to_str().unwrap(), "20"], None);
    assert_eq!(ok_stdout(&out), expected);
    assert!(out.stderr.is_empty());
}

fn particles(input: &str, t: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let f = write(&dir, "in.txt", input);
    ok_stdout(&run("particles", &[&f, t], None))
}

#[test]
fn walls_only() {
    // R = 1, box 10 x 8, from (5, 4) at (1, 0.5). x: hits x = 9 at t = 4, back to 3 at t = 10.
    // y: hits y = 7 at t = 6, back to 5 at t = 10. Three wall collisions... two: x once, y once.
    assert_eq!(
        particles("1\n1\n10 8\n5 4 1 0.5\n", "10"),
        "3.000000, 5.000000, 2, 0\n"
    );
}

#[test]
fn disc_aimed_at_a_corner_counts_two_wall_collisions() {
    // R = 1, box 10 x 10, from (5, 5) at (1, 1): touches x = 9 and y = 9 together at t = 4,
    // then returns along the diagonal: (7, 7) at t = 6.
    assert_eq!(
        particles("1\n1\n10 10\n5 5 1 1\n", "6"),
        "7.000000, 7.000000, 2, 0\n"
    );
}

#[test]
fn head_on_pair_swaps_velocities() {
    // R = 1: centres 10 apart, gap 8 closing at 2 -> contact at t = 4 at x = 9 and 11; after the
    // swap they go back: at t = 6, x = 7 and 13.
    let out = particles("2\n1\n20 10\n5 5 1 0\n15 5 -1 0\n", "6");
    assert_eq!(out, "7.000000, 5.000000, 0, 1\n13.000000, 5.000000, 0, 1\n");
}

#[test]
fn oblique_pair_swaps_whole_velocities() {
    // R = 2.5 (contact distance 5). Disc 0 from (5, 10) at (1, 0); disc 1 at rest at (13, 14).
    // dr = (8, 4), dv = (-1, 0): b = -8, c = 80 - 25 = 55, d = 64 - 55 = 9,
    // t = c / (-b + sqrt d) = 55 / 11 = 5 (line of centres (3, 4)). The course rule swaps the
    // velocities: disc 0 stops at (10, 10), disc 1 leaves at (1, 0) and is at (16, 14) at t = 8.
    let out = particles("2\n2.5\n30 30\n5 10 1 0\n13 14 0 0\n", "8");
    assert_eq!(
        out,
        "10.000000, 10.000000, 0, 1\n16.000000, 14.000000, 0, 1\n"
    );
}

#[test]
fn collisions_exactly_at_the_end_time_are_processed() {
    // The wall contact is at t = 4 exactly: "processed until the collision time would be
    // greater than the end time".
    assert_eq!(
        particles("1\n1\n10 10\n5 5 1 0.5\n", "4"),
        "9.000000, 7.000000, 1, 0\n"
    );
}

#[test]
fn runs_one_hundred_thousand_discs() {
    // 100000 discs of radius 0.1 on a 400 x 250 grid with spacing 1 in a 400 x 250 box.
    let mut text = String::from("100000\n0.1\n400 250\n");
    for k in 0..100_000u64 {
        let (i, j) = (k % 400, k / 400);
        let (u, v) = (
            ((k * 7919) % 200) as f64 / 100.0 - 1.0,
            ((k * 104729) % 200) as f64 / 100.0 - 0.995,
        );
        text += &format!("{}.5 {}.5 {u} {v}\n", i, j);
    }
    let out = particles(&text, "2");
    assert_eq!(out.lines().count(), 100_000);
    let collisions: u64 = out
        .lines()
        .map(|l| l.rsplit(", ").next().unwrap().parse::<u64>().unwrap())
        .sum();
    assert!(collisions > 1000, "{collisions}");
}
