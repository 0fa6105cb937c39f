"""One colour per user, shared by every effect that colours by performer, so a dancer is the
same colour in the trails, the silhouette and the sparks."""
from __future__ import annotations

#: Bright, distinct colours (RGB, 0..1) for users 1, 2, 3, ...; picked to stay apart on a black
#: stage and to each other. More than eight users cycle (user 9 is user 1's colour).
USER_COLOURS: tuple[tuple[float, float, float], ...] = (
    (1.0, 0.3, 0.2),    # red
    (0.2, 0.9, 0.3),    # green
    (0.25, 0.5, 1.0),   # blue
    (1.0, 0.85, 0.1),   # yellow
    (0.9, 0.3, 1.0),    # violet
    (0.1, 0.9, 0.9),    # cyan
    (1.0, 0.55, 0.0),   # orange
    (1.0, 0.5, 0.75),   # pink
)


def user_colour(user_id: int) -> tuple[float, float, float]:
    """The colour of user `user_id` (ids start at 1; the same id always gets the same colour). A
    shader gets the same from `USER_COLOURS[(id - 1) % len(USER_COLOURS)]`."""
    return USER_COLOURS[(user_id - 1) % len(USER_COLOURS)]
