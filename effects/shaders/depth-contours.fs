/*{
    "DESCRIPTION": "Contour lines of the depth image, like a topographic map of the performer, drifting towards the camera; they flash on every wave.",
    "CREDIT": "issv",
    "ISFVSN": "2",
    "CATEGORIES": ["Stylize"],
    "INPUTS": [
        {"NAME": "depthImage", "TYPE": "image"},
        {"NAME": "flash", "TYPE": "float", "DEFAULT": 10000.0},
        {"NAME": "spacing", "TYPE": "float", "DEFAULT": 0.08, "MIN": 0.01, "MAX": 1.0},
        {"NAME": "speed", "TYPE": "float", "DEFAULT": 0.05},
        {"NAME": "nearColor", "TYPE": "color", "DEFAULT": [0.2, 1.0, 0.7, 1.0]},
        {"NAME": "farColor", "TYPE": "color", "DEFAULT": [0.5, 0.2, 1.0, 1.0]}
    ]
}*/

void main() {
    float d = IMG_NORM_PIXEL(depthImage, isf_FragNormCoord).r;   // metres, 0 = no reading
    if (d <= 0.0) {
        gl_FragColor = vec4(0.0);
        return;
    }
    float phase = fract(d / spacing + TIME * speed / spacing);
    float line = smoothstep(0.12, 0.0, abs(phase - 0.5) - 0.38);
    vec3 col = mix(nearColor.rgb, farColor.rgb, clamp((d - 1.0) / 3.0, 0.0, 1.0));
    float boost = 1.0 + 2.0 * exp(-flash * 4.0);
    gl_FragColor = vec4(col * boost, line * 0.9);
}
