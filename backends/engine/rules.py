"""Every threshold of the gesture recogniser, in millimetres and seconds, in one place.

A profile overrides any of them through its backend options, e.g.
`[backend] name = "openiss"  gestures = {swipe_min_travel_mm = 300}`. The defaults describe an adult
performer moving deliberately; they are physical and relative to the body (the torso and head
reference points), never derived from one performer's recordings or normalised per clip.
Positions are camera coordinates (x towards the image's right, y up, z away from the camera);
"forward" means towards the camera.
"""
from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field


class GestureRules(BaseModel):
    """Thresholds of the recogniser. Distances in mm, durations in s, speeds in mm/s."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    # --- segmentation of motion into strokes (runs of motion along one axis) -------------------
    stroke_hysteresis_mm: float = Field(
        40.0, gt=0, description="a stroke reverses only after the hand comes back this far from its extreme: "
        "above the jitter of skeleton and depth hand trackers (10-20 mm), below a wave's swing")
    stroke_stop_s: float = Field(
        0.12, gt=0, description="a stroke ends when its extreme has not advanced for this long (the hand stopped)")
    stroke_min_reversal_s: float = Field(
        0.07, ge=0, description="a reversal that lasts no longer than this (two frames at 30 Hz) before the hand "
        "goes on its way again, beyond where it turned, is a tracker's jitter, not a motion: the strokes either "
        "side of it are one (a hand coming back only as far made a quick swing)")
    track_gap_s: float = Field(
        0.1, gt=0, description="a hand not reported for longer than this (three frames at 30 Hz) left a gap: "
        "where it went meanwhile is unknown")
    speed_window_s: float = Field(
        0.06, gt=0, description="speeds are measured over this interval (two frames at 30 Hz)")
    stroke_core_speed_fraction: float = Field(
        0.25, ge=0, lt=1, description="a stroke is judged on its core, the samples moving faster than this "
        "share of its peak speed (or than `stroke_core_speed_mm_s`, if lower): the slow start of an arc "
        "and the settling at its end are not the gesture")
    stroke_core_speed_mm_s: float = Field(
        500.0, gt=0, description="samples moving faster than this are always in the core, however fast the "
        "peak (a flick caught by one or two frames at 30 Hz must not shrink the stroke to those frames)")
    active_min_height_mm: float = Field(
        -150.0, description="a hand lower than this relative to the torso (the spine joint) hangs at rest: "
        "swipes and clicks must start and end above it, so lifting the arm from rest or dropping it "
        "back is never a gesture (a hanging hand is 300-400 mm below the torso); a wave's opening swing, the arm "
        "swinging up into it, may start from anywhere above it (see `wave_arc_below_shoulder_mm`)")

    # --- swipes -------------------------------------------------------------------------------
    swipe_min_travel_mm: float = Field(
        350.0, gt=0, description="net travel along the swipe direction, relative to the body (sideways: for "
        "an adult, scaled to the performer's size, as their arms reach less far; up or down it stays an "
        "adult's: scaled, smaller performers reaching over the shoulder and back, MSRC-12's change weapon, "
        "fired swipes up and down)")
    swipe_max_duration_s: float = Field(
        1.5, gt=0, description="a slower stroke (its core, as fast as `swipe_min_peak_speed_mm_s` at its peak) "
        "is a reach, not a swipe; a sweep of a whole arm's span by a slow or tall performer takes longer than a "
        "short one: MSRC-12 p02's 1 m push right lasts 0.85 s, 1.12 s played 1.4 times slower")
    swipe_min_peak_speed_mm_s: float = Field(
        1000.0, gt=0, description="peak speed along the swipe direction (a deliberate swipe peaks at 1.5-3 m/s)")
    swipe_low_min_height_mm: float = Field(
        -300.0, description="a sideways swipe may dip below `active_min_height_mm` down to this (relative to the "
        "torso, for an adult; waist height), when it sweeps outwards and ends `swipe_low_min_reach_mm` out on the "
        "hand's own side: the arm is then held away from the body")
    swipe_low_min_reach_mm: float = Field(
        350.0, gt=0, description="how far out from the spine, on its own side, such a low swipe must end "
        "(beyond the shoulder: a hanging hand is 150-250 mm out)")
    swipe_across_min_reach_mm: float = Field(
        350.0, gt=0, description="a swipe across the body straight from the hanging arm (rising from its side "
        "across the spine in one diagonal, out to an imaginary screen) ends at least this far in front of the "
        "torso (for an adult, scaled to the performer's size): a hand brought to the chest to wind up a push or "
        "a swipe back ends closer")
    swipe_across_max_above_shoulder_mm: float = Field(
        100.0, description="such a swipe ends no higher than this above the shoulder line (about the chin; for an "
        "adult, scaled to the performer's size): a hand reaching over the shoulder (MSRC-12's change weapon) or "
        "to the head goes higher")
    swipe_vertical_max_head_move_mm: float = Field(
        80.0, gt=0, description="during a swipe up or down the head moves no more than this relative to the torso "
        "(for an adult, scaled to the performer's size): the arm moves, the body stays; an arm thrown up or "
        "down while the body bends, kicks or twists moves the head 90-180 mm")
    swipe_dominance: float = Field(
        1.5, ge=1, description="travel along the swipe direction over the largest travel along the other axes: "
        "diagonal wind-ups and returns stay below it")
    swipe_level_dominance: float = Field(
        5.0, ge=1, description="a sweep sideways that does not fall (rising, or falling at most 1/this of its "
        "travel: 11 degrees), the hand above `active_min_height_mm` throughout, is an arm swinging about its "
        "shoulder: its hand comes back towards the body's plane (the torso's depth) by up to as far as it "
        "sweeps across (a quarter circle), and that depth does not count against `swipe_dominance`; moving "
        "forwards, back further or behind the body does. An arm swinging back to throw, run or kick falls, "
        "or ends behind the body")
    vertical_swipe_seen_before_s: float = Field(
        0.1, ge=0, description="a swipe up or down must start after its hand has been seen without a gap "
        "for this long, and the hand must still be seen right after it: a hand found mid-rise may be "
        "lifting from a rest where a depth tracker could not tell it from the body, one lost at the end "
        "of a drop may be going back there")
    swipe_confirm_s: float = Field(
        0.12, ge=0, description="after a stroke ends, how long to watch whether a comparable stroke the other "
        "way follows (then the stronger of the two is the swipe, the other its wind-up or return, or both "
        "belong to a wave); this is the latency of a swipe that may be a wind-up (see `swipe_sure_reach_mm`). "
        "A sideways stroke the hand turned straight into is watched to its end")
    swipe_rest_s: float = Field(
        0.3, ge=0, description="a sideways swipe started from rest when its hand, seen throughout, moved less "
        "than `swipe_rest_mm` along the swipe's axis over this long before it (a wind-up or a wave's swing "
        "just before it moved the hand)")
    swipe_rest_mm: float = Field(
        150.0, gt=0, description="see `swipe_rest_s` (for an adult, scaled to the performer's size)")
    swipe_sure_reach_mm: float = Field(
        350.0, gt=0, description="a sideways swipe from rest, sweeping outwards to at least this far out from "
        "the spine on its hand's own side (beyond the shoulder, the arm held out), with no other hand moving "
        "by `swipe_comparable_ratio` of its travel, is no wind-up: it completes without `swipe_confirm_s`, "
        "as soon as it settles; if it travels at least an adult's `swipe_min_travel_mm` (a child's shorter "
        "stroke out from rest may wind up a swipe across: it waits)")
    swipe_sure_start_mm: float = Field(
        150.0, description="and starts in front of the body: no further out than this from the spine on its "
        "hand's own side, inside the shoulder (MSRC-12's pushes to the side start 300 mm across the body to "
        "113 mm out; a hand drawn out from in front of its shoulder to wind up a swipe the other way starts "
        "further out). Further out, the swipe waits `swipe_confirm_s` like any other")
    swipe_settle_fraction: float = Field(
        0.35, ge=0, le=1, description="such a swipe has settled once its speed along its axis falls below "
        "this share of its peak (the arm decelerates into its reach: little travel is left)")
    swipe_comparable_ratio: float = Field(
        0.4, gt=0, le=1, description="a following opposite stroke with at least this share of the first's "
        "travel, fast and dominant like a swipe, is compared with it: the stronger (travel times mean speed) "
        "is the swipe, the weaker its wind-up or return (or both are part of a wave); another hand "
        "moving the other way by this share at the same time makes it two-handed (a clap), not a swipe or wave")

    # --- wave (and oscillations in general) ------------------------------------------------------
    oscillation_max_gap_s: float = Field(
        0.3, ge=0, description="alternating strokes belong to one oscillation (a wave, a back-and-forth) "
        "when the next starts within this long of the previous one's end")
    oscillation_min_travel_mm: float = Field(
        100.0, gt=0, description="a stroke this long or longer counts in a back-and-forth: the third of "
        "quick alternating strokes at a wave's height is never a swipe")
    oscillation_min_dominance: float = Field(
        1.0, gt=0, description="an oscillation's strokes run mostly along their axis (travel over the "
        "largest travel across it)")
    wave_min_amplitude_mm: float = Field(
        40.0, gt=0, description="horizontal swing of every side-to-side stroke of a wave (a hand waving "
        "from the wrist swings the hand joint 40-80 mm; below that a skeleton's jitter could count)")
    wave_min_typical_amplitude_mm: float = Field(
        50.0, gt=0, description="median swing of the wave's strokes (a hand waving from the wrist: 5-10 cm, "
        "a forearm about the elbow: 20-40 cm, a whole arm more)")
    wave_min_dominance: float = Field(
        0.5, gt=0, description="a wave's swing runs at least this much more sideways than up, down or "
        "forward (a forearm swinging about the elbow moves the hand along an arc)")
    wave_arc_below_shoulder_mm: float = Field(
        350.0, description="a whole arm waving dips this far below the shoulders at the bottom of its arc "
        "(the swing's highest point is judged by `wave_max_below_shoulder_mm`); a hand on the hip or "
        "hanging is lower. The wave's opening swing may start lower when the arm swings up into it: rising "
        "from above `active_min_height_mm`, its lowest point where it starts (within `stroke_hysteresis_mm`); "
        "a whole arm lifted out to the side and swung up across opens 290-390 mm below the shoulders")
    wave_min_swing_s: float = Field(
        0.1, ge=0, description="median duration of a wave's swings: nobody waves faster than 5 Hz; "
        "quicker reversals are a skeleton's jitter or glitches")
    wave_min_hands_apart_mm: float = Field(
        400.0, ge=0, description="a wave is made by one hand, the other kept at least this far from it "
        "(hands clapping, rubbing, at the eyes or on the head are close together)")
    wave_max_stroke_s: float = Field(0.5, gt=0, description="a slower side-to-side stroke is not waving "
        "(waves swing at 1-4 Hz: 0.12-0.5 s a swing)")
    wave_max_tilt_deg: float = Field(
        20.0, ge=0, description="a wave is made with the body upright: the line from the torso to the head "
        "within this angle of straight up (waves: up to 12 degrees; leaning to the side, bowing or lunging, "
        "hands on the hips or swinging sweep sideways relative to the tilted torso)")
    wave_min_reversals: int = Field(3, ge=1, description="direction reversals needed: 3 = right-left-right-left")
    wave_max_below_shoulder_mm: float = Field(
        150.0, description="every swing of a wave reaches no lower than this below the shoulders: in "
        "front of the chest or higher (a hand swinging at the hip while walking is no wave)")
    wave_top_below_shoulder_mm: float = Field(
        30.0, description="and the highest swing reaches the shoulders, or no lower than this below them "
        "(for an adult, scaled to the performer's size): Kinder-Gator's adults wave no lower than 20 mm "
        "under them, an arm swinging across the chest while jogging stays 70-130 mm under")
    # a wave told by its rhythm (rhythm.py): swings too small for strokes, from the wrist or the fingers
    wave_rhythm_hysteresis_mm: float = Field(
        6.0, gt=0, description="a wave's side-to-side swing, however small, turns once the hand comes back "
        "this far (a hand waved with the fingers swings the skeleton's hand joint 8-25 mm; the jitter of a "
        "still hand reverses as much, but within a frame or two, quicker than any wave's swing)")
    wave_rhythm_max_swing_s: float = Field(
        0.33, gt=0, description="such a swing lasts from `wave_min_swing_s` to this (waving at 1.5-5 Hz); a "
        "hand held at one side longer breaks the rhythm")
    wave_rhythm_min_dominance: float = Field(
        1.4, gt=0, description="and runs sideways this many times further than the hand moves up, down, "
        "forward or back meanwhile (a raised hand's jitter and fidgeting move it along every axis alike)")
    wave_rhythm_max_below_shoulder_mm: float = Field(
        0.0, description="with the hand no lower than this below the shoulders throughout (the hand held up)")
    wave_rhythm_min_swings: int = Field(
        6, ge=2, description="that many such swings in a row are a wave (three times back and forth: a raised "
        "hand's jitter or fidgeting keeps time for at most four)")

    # --- click / push -------------------------------------------------------------------------
    click_min_travel_mm: float = Field(200.0, gt=0, description="forward travel towards the camera")
    click_min_duration_s: float = Field(
        0.1, ge=0, description="a forward jump quicker than this is a tracking glitch, not a push (a depth "
        "tracker sees a fast push only once the hand is off the chest: three frames at 30 Hz)")
    click_max_duration_s: float = Field(
        1.5, gt=0, description="a slower forward motion is no push (pushes from a hanging hand, rising as they "
        "go, take 0.3-0.85 s, a child's the slowest, and a push from the hip to arm's length at a child's "
        "deliberate pace 1.2-1.3 s; what moves forward slower is too slow for a push's speed anyway)")
    click_min_peak_speed_mm_s: float = Field(700.0, gt=0, description="peak forward speed")
    click_halt_max_speed_mm_s: float = Field(
        1000.0, gt=0, description="at its furthest point the hand nearly halts (stops or comes back): "
        "its speed there falls below this (an arm uncurling down past it does not)")
    click_dominance: float = Field(
        1.5, ge=1, description="forward travel over sideways travel; and over the last `click_end_mm` "
        "the motion runs this much more forward than sideways or vertically (a push from a hanging hand "
        "rises as much as it goes forward, but ends straight ahead)")
    click_end_mm: float = Field(150.0, gt=0, description="the last stretch of a push, judged for its direction")
    click_end_dominance: float = Field(
        0.4, ge=0, description="over the last `click_end_mm` the hand still heads forward: forward travel "
        "over sideways or vertical travel (a push from a hanging hand arcs up and forward to the end)")
    swing_max_stroke_s: float = Field(
        0.5, gt=0, description="arms swinging back and forth while running or walking take at most this "
        "long a swing; a push that comes after two such swings back and forth is a swing too")
    click_min_forward_per_rise: float = Field(
        0.6, ge=0, description="a push goes forward at least this share of how far it rises, from where it "
        "heads forward at least as fast as it rises if it still goes `click_end_mm` forward from there (a push "
        "that follows a rise from hanging without a stop is judged from its turn forward; an arm lifted from "
        "the side to start a swipe, or to point, rises more than it comes forward)")
    click_hanging_below_shoulder_mm: float = Field(
        300.0, gt=0, description="a push that starts this far below the shoulders starts from a hanging "
        "hand; then another hand rising forward with it makes both arms' swing (squat, jump), no push")
    click_squat_watch_s: float = Field(
        0.6, ge=0, description="both hands pushed forward together from hanging at the sides are a push only if, "
        "with a skeleton to tell, the body stays up (`steady_body_max_vertical_speed_mm_s`) until this long "
        "after it: a squat's arms rise before the body sinks (0.3-0.5 s later); without a skeleton, never")
    click_min_reach_mm: float = Field(
        400.0, gt=0, description="the push ends at least this far in front of the torso (an arm stretched "
        "out: 500-650 mm; arms swinging while walking, running or kicking stay nearer)")
    click_max_below_shoulder_mm: float = Field(
        200.0, description="and no lower than this below the shoulders (a button is pushed at chest height)")

    # --- hand raise ---------------------------------------------------------------------------
    raise_min_above_head_mm: float = Field(
        50.0, description="the hand is at least this far above the head's centre")
    raise_clear_of_head_mm: float = Field(
        300.0, gt=0, description="and at least this far from the head's centre: hands put on the head "
        "(protest, despair) rest within 150-250 mm of it, a raised arm's hand 400-700 mm")
    raise_past_head_s: float = Field(
        0.2, ge=0, description="a raised hand that comes within `raise_clear_of_head_mm` of the head for no longer "
        "than this passes it and stays raised: arms lifted overhead that bring the hands together just above the "
        "head (MSRC-12's p02: 0.03-0.4 s, median 0.1 s), or a jittery tracker's hand held near that distance; one "
        "that stays longer was put there (hands on the head rest there for seconds, median 1.1 s between moments "
        "clear of it)")
    raise_min_up_s: float = Field(
        0.1, gt=0, description="up and clear for at least this long (three frames at 30 Hz)")
    raise_max_speed_mm_s: float = Field(
        600.0, gt=0, description="and then nearly stopping: the top of a lift, or a hand held up "
        "(a hand still rising, or sweeping across in a wave, moves faster)")
    raise_still_s: float = Field(
        0.06, ge=0, description="for this long: a waving hand slows only for an instant where it turns")
    raise_hold_s: float = Field(
        0.7, gt=0, description="or up and clear of the head this long without a break, however it moves (arms "
        "lifted overhead may flap or shake and never stop; a hand on the head strays clear of it only for "
        "moments)")

    # --- per hand -----------------------------------------------------------------------------
    refractory_s: float = Field(
        0.6, ge=0, description="after a COMPLETE gesture the same hand completes no other for this long "
        "(the return of a swipe or a push is not a gesture), but a hand raise after a swipe up (the hand held "
        "up where the swipe took it)")
    forget_after_s: float = Field(
        0.5, gt=0, description="a hand not reported for this long is forgotten (a LOST hand at once)")

    # --- the body ----------------------------------------------------------------------------
    body_hold_s: float = Field(
        1.0, ge=0, description="body points missing from a frame are taken as unchanged for this long "
        "(a skeleton that flickers must not make the hands jump relative to the body)")
    steady_body_max_vertical_speed_mm_s: float = Field(
        350.0, gt=0, description="no swipe or click while the torso rises or sinks faster than this "
        "(squatting, sitting down, lunging: the arms move for balance)")
    steady_body_max_depth_move_mm: float = Field(
        100.0, gt=0, description="no swipe while the torso moves further than this towards or away from the "
        "camera within `steady_body_depth_window_s`, from that long before its stroke until it completes (for "
        "an adult, scaled to the performer's size): most kicks move it 150-290 mm in that time, an arm swinging "
        "across the body for balance. Real swipes move it 40 mm at most, pushes 55 mm as a depth tracker sees "
        "it (UTD-MHAD). Sideways the body may move: a swipe may carry it, leaning "
        "into the sweep. Only with a skeleton to tell")
    steady_body_depth_window_s: float = Field(
        0.3, gt=0, description="see `steady_body_max_depth_move_mm`: a kick or a lunge rocks the torso for "
        "0.3-0.5 s, a depth tracker's torso that jumps for a frame drifts back within it")
    body_speed_window_s: float = Field(
        0.2, gt=0, description="the torso's speed is measured over this interval (longer than for hands: "
        "a skeleton's torso jitters by several mm per frame, a squat lasts a second)")
    # without a skeleton, or with only part of one
    head_above_torso_mm: float = Field(
        520.0, gt=0, description="head centre above the torso (spine) joint of an adult: used when only "
        "the torso is known, and the body size for which every distance threshold here is stated. "
        "They scale with the performer's own torso-to-head distance (a child of five: about 400 mm), "
        "within `body_size_range`")
    body_size_range: tuple[float, float] = Field(
        (0.6, 1.3), description="the smallest and largest performer, relative to `head_above_torso_mm`, "
        "that distance thresholds follow (a skeleton glitch must not shrink them to nothing)")
    shoulder_below_head_mm: float = Field(
        250.0, gt=0, description="shoulder line below the head's centre (for an adult, scaled to the performer's size)")
    rest_below_torso_mm: float = Field(
        320.0, gt=0, description="without a skeleton: a hand hanging at rest is this far below the torso, "
        "so the torso is estimated from the lowest hand over the last `body_window_s`")
    rest_in_front_of_torso_mm: float = Field(
        80.0, description="without a skeleton: a hanging hand is this far in front of the torso")
    body_max_acceleration_mm_s2: float = Field(
        2000.0, gt=0, description="without a skeleton: the body's estimated motion changes speed no faster "
        "than this (starting to walk takes 1-2 m/s^2; hands in a push reach 10-20 m/s^2)")
    body_window_s: float = Field(
        3.0, gt=0, description="without a skeleton: how far back the resting hand is looked for")

    def size(self, head_above_torso_mm: float) -> float:
        """The performer's size relative to the adult the distance thresholds are stated for, from
        their head's height above the torso (`head_above_torso_mm`, within `body_size_range`)."""
        lo, hi = self.body_size_range
        return min(max(head_above_torso_mm / self.head_above_torso_mm, lo), hi)
