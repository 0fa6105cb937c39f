"""bench.people's picture: every person's recall of every gesture, per dataset."""
import math

from bench.person_plot import _grid, _label, plot_people

FIG = {"by_person": {"swipe_left/adults": {"p565": 0.0, "p604": 1.0}, "wave/children": {"p106": 0.5}},
       "false_fire_rate": {"adults": 0.02, "children": None}, "worst_person_overall": 0.43}


def test_each_cell_is_one_person_s_recall_of_one_gesture_and_empty_where_they_did_not_perform_it():
    gestures, persons, cells = _grid(FIG)
    assert gestures == ["swipe_left/adults", "wave/children"]
    assert persons == ["p106", "p565", "p604"]
    assert [cells[0][1], cells[0][2], cells[1][0]] == [0.0, 1.0, 0.5]
    assert math.isnan(cells[0][0]) and math.isnan(cells[1][1])
    assert [_label(0.0), _label(1.0), _label(0.857)] == ["0", "1", ".86"]


def test_the_plot_has_a_panel_per_dataset_and_section(tmp_path):
    import matplotlib.image

    out = {"default": {"kinder": FIG, "msrc": {"by_person": {"hand_raise": {"p02": 0.86}}, "false_fire_rate": 0.05}}}
    path = tmp_path / "people.png"
    plot_people(out, path)
    one = matplotlib.image.imread(path)
    out["leave_one_person_out"] = out["default"]
    plot_people(out, path)
    two = matplotlib.image.imread(path)
    assert two.shape[0] > 1.8 * one.shape[0] and two.shape[1] == one.shape[1]


def test_a_choice_that_fires_another_gesture_besides_the_right_one_scores_lower():
    """Leave one person out chooses by recall less false fires less confusions: the same recall with a
    swipe that also fires a swipe back is the worse choice (a wrong effect on stage)."""
    from bench.people import Outcome, Recording, _score

    recordings = [Recording("a.csv", "kinder", "p1", "swipe_left", group="children"),
                  Recording("b.csv", "kinder", "p1", None, negative=True, group="children")]
    clean = [Outcome(hits=[True]), Outcome(negatives=[False])]
    confused = [Outcome(hits=[True], confused=True), Outcome(negatives=[False])]
    fired = [Outcome(hits=[True]), Outcome(negatives=[True])]
    assert _score(recordings, clean) == 1.0
    assert _score(recordings, confused) == _score(recordings, fired) == 0.0
