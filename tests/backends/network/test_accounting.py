"""Loss, duplicates, tail loss and restarts are counted from sequence numbers and sessions."""
from __future__ import annotations

import time

from backends.network import wire
from backends.network.subscriber import BYE_GRACE_S, SILENCE_S, Accounting


def hands(session: int, seq: int) -> wire.HandsMsg:
    return wire.HandsMsg(wire.Header(wire.HANDS, session, seq, time.time()), seq, 0.0, "x", (), False)


def status(session: int, kind: int, hands_last: int) -> wire.StatusMsg:
    return wire.StatusMsg(wire.Header(kind, session, 0, time.time()), {"depth": 0, "hands": hands_last,
                                                                        "gestures": 0}, "x", 0)


def test_gaps_duplicates_tail_and_restart():
    notes: list[str] = []
    acc = Accounting("tcp://here:1", notes.append)
    assert [acc.accept(hands(1, s)) for s in (5, 6, 8, 8, 7)] == [True, True, True, False, False]
    s = acc.to_json()["streams"]["hands"]
    assert (s["received"], s["lost"], s["duplicates"]) == (3, 1, 2)  # joined at 5: 1-4 are not loss
    acc.accept(status(1, wire.HEARTBEAT, 10))  # 9 and 10 were sent: in flight or lost
    assert acc.to_json()["streams"]["hands"]["lost"] == 3
    acc.accept(hands(2, 1))  # a new session: the publisher restarted
    assert acc.restarts == 1 and sum("restarted" in n for n in notes) == 1
    assert not acc.accept(hands(1, 11))  # a late message of the old run is stale, not a restart back
    assert acc.restarts == 1 and acc.stale == 1
    assert acc.to_json()["streams"]["hands"]["lost"] == 3


def test_until_a_publisher_is_heard_it_says_once_where_it_waits_and_what_to_start():
    notes: list[str] = []
    acc = Accounting("tcp://cam:1", notes.append, "on cam: issv serve PROFILE --bind tcp://0.0.0.0:1")
    waiting = "no publisher at tcp://cam:1 yet (start one on cam: issv serve PROFILE --bind tcp://0.0.0.0:1)"
    assert acc.waiting() == waiting
    acc.last_message -= SILENCE_S + 1
    acc.check_silence()
    acc.check_silence()
    assert notes == [f"{waiting}; the show waits for it"]
    acc.accept(hands(1, 1))
    assert acc.waiting() is None and notes[-1] == "publisher at tcp://cam:1 found; receiving"


def test_after_a_goodbye_the_messages_it_announced_are_awaited_a_moment_not_counted_lost():
    """Over ROS each topic is its own connection: the goodbye may arrive before the last hands."""
    acc = Accounting("http://master:1", lambda text: None)
    acc.accept(hands(1, 1))
    acc.accept(status(1, wire.BYE, 2))
    assert acc.ended and not acc.settled()  # hands 2 is on its way
    acc.accept(hands(1, 2))
    assert acc.settled() and acc.to_json()["streams"]["hands"]["lost"] == 0
    acc.accept(status(1, wire.BYE, 3))  # one that never comes: lost once the grace is over
    acc.ended_at -= BYE_GRACE_S
    assert acc.settled() and acc.to_json()["streams"]["hands"]["lost"] == 1
