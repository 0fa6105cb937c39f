/*{
    "DESCRIPTION": "The performer (depth nearer than `far` metres) as a faint body crossed by contour lines, like a topographic map, drifting towards the camera; they flash on every wave.",
    "CREDIT": "issv",
    "ISFVSN": "2",
    "CATEGORIES": ["Stylize"],
    "INPUTS": [
        {"NAME": "depthImage", "TYPE": "image"},
        {"NAME": "flash", "TYPE": "float", "DEFAULT": 10000.0},
        {"NAME": "far", "TYPE": "float", "DEFAULT": 3.2, "MIN": 0.5, "MAX": 10.0},
        {"NAME": "body", "TYPE": "float", "DEFAULT": 0.0, "MIN": 0.0, "MAX": 1.0},
        {"NAME": "spacing", "TYPE": "float", "DEFAULT": 0.08, "MIN": 0.01, "MAX": 1.0},
        {"NAME": "speed", "TYPE": "float", "DEFAULT": 0.05},
        {"NAME": "nearColor", "TYPE": "color", "DEFAULT": [0.2, 1.0, 0.7, 1.0]},
        {"NAME": "farColor", "TYPE": "color", "DEFAULT": [0.5, 0.2, 1.0, 1.0]}
    ]
}*/

// Per-frame values from the vertex shader (depth-contours.vs): a CPU rasteriser pays for every
// instruction per pixel, so nothing that is the same for the whole frame is computed here.
flat in float invSpacing;   // 1 / spacing
flat in float drift;        // TIME * speed / spacing
flat in float boost;        // the flash on a wave

void main() {
    float d = IMG_NORM_PIXEL(depthImage, isf_FragNormCoord).r;   // metres, 0 = no reading
    if (d <= 0.0 || d > far) {   // no reading, or the room behind the performer
        gl_FragColor = vec4(0.0);
        return;
    }
    float phase = fract(d * invSpacing + drift);
    float line = 1.0 - smoothstep(0.04, 0.1, min(phase, 1.0 - phase));   // near a contour
    vec3 col = mix(nearColor.rgb, farColor.rgb, clamp((d - 1.0) * (1.0 / 3.0), 0.0, 1.0));
    gl_FragColor = vec4(col * boost, max(line * 0.9, body));
}
