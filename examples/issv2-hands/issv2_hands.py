"""SimpleOpenNI's "Hands" sketch, ported from ISSv2's Processing to issv with SimpleOpenNIEffect.

The sketch kept a path of the last positions of every hand (handPathList), printed its
callbacks, and drew each path as a coloured line with a dot at the hand. The callback bodies
below are the sketch's, line for line; what went away: `context.enableHand()`,
`context.startGesture(...)` and `context.startTrackingHand(pos)` in onCompletedGesture (every
backend tracks hands by itself), and PVector (positions are (x, y, z) tuples in mm).
"""
from __future__ import annotations

import numpy as np

from host import SimpleOpenNIEffect, hookimpl

HAND_VEC_LIST_SIZE = 20
USER_CLR = [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (1.0, 1.0, 0.0), (1.0, 0.0, 1.0), (0.0, 1.0, 1.0)]

VERTEX = """
#version 330
uniform mat3 to_clip;  // output pixels -> clip space, keystone included (the host's target.to_clip)
in vec2 in_pos;
void main() { vec3 p = to_clip * vec3(in_pos, 1.0); gl_Position = vec4(p.xy, 0.0, p.z); }
"""
FRAGMENT = """
#version 330
uniform vec3 stroke;
out vec4 color;
void main() { color = vec4(stroke, 1.0); }
"""


class Hands(SimpleOpenNIEffect):
    name = "issv2-hands"
    renders = True

    def setup(self, stage) -> None:
        super().setup(stage)
        self.hand_path_list: dict[int, list[tuple[float, float, float]]] = {}
        self.depth = None
        if stage.ctx is not None:
            self.prog = stage.ctx.program(vertex_shader=VERTEX, fragment_shader=FRAGMENT)
            self.vbo = stage.ctx.buffer(reserve=HAND_VEC_LIST_SIZE * 8)
            self.vao = stage.ctx.vertex_array(self.prog, [(self.vbo, "2f", "in_pos")])

    # -- the sketch's callbacks ------------------------------------------------------------
    def on_new_hand(self, hand_id, pos) -> None:
        print(f"onNewHand - handId: {hand_id}, pos: {pos}")
        self.hand_path_list[hand_id] = [pos]

    def on_tracked_hand(self, hand_id, pos) -> None:
        vec_list = self.hand_path_list.get(hand_id)
        if vec_list is not None:
            vec_list.insert(0, pos)
            if len(vec_list) >= HAND_VEC_LIST_SIZE:
                vec_list.pop()  # remove the oldest point

    def on_lost_hand(self, hand_id) -> None:
        print(f"onLostHand - handId: {hand_id}")
        self.hand_path_list.pop(hand_id, None)

    def on_completed_gesture(self, gesture_type, pos) -> None:
        print(f"onCompletedGesture - gestureType: {gesture_type.value}, pos: {pos}")

    # -- draw() ----------------------------------------------------------------------------
    def on_frame(self, frame) -> None:
        super().on_frame(frame)  # keeps the callbacks coming
        self.depth = frame.depth

    def render(self, target) -> None:
        if self.depth is None:
            return
        self.prog["to_clip"].write(np.asarray(target.to_clip, "f4").T.tobytes())  # GLSL is column-major
        for hand_id, vec_list in self.hand_path_list.items():
            points = np.array([self.stage.to_stage(p, self.depth) for p in vec_list], "f4")
            self.vbo.write(points.tobytes())
            self.prog["stroke"] = USER_CLR[(hand_id - 1) % len(USER_CLR)]
            self.vao.render(mode=self.stage.ctx.LINE_STRIP, vertices=len(points))
            self.stage.ctx.point_size = 8.0
            self.vao.render(mode=self.stage.ctx.POINTS, vertices=1)  # the hand itself

    def close(self) -> None:
        if getattr(self, "vao", None) is not None:
            for obj in (self.vao, self.vbo, self.prog):
                obj.release()


@hookimpl
def register_effects(register):
    register(Hands)
