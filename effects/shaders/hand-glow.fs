/*{
    "DESCRIPTION": "Two hands as soft coloured lights that melt together when close; a ring of light spreads from where the last gesture completed.",
    "CREDIT": "issv",
    "ISFVSN": "2",
    "CATEGORIES": ["Generator"],
    "INPUTS": [
        {"NAME": "handA", "TYPE": "point2D", "DEFAULT": [-10000.0, -10000.0]},
        {"NAME": "handB", "TYPE": "point2D", "DEFAULT": [-10000.0, -10000.0]},
        {"NAME": "burstPos", "TYPE": "point2D", "DEFAULT": [-10000.0, -10000.0]},
        {"NAME": "burstAge", "TYPE": "float", "DEFAULT": 10000.0},
        {"NAME": "colorA", "TYPE": "color", "DEFAULT": [1.0, 0.35, 0.1, 1.0]},
        {"NAME": "colorB", "TYPE": "color", "DEFAULT": [0.1, 0.5, 1.0, 1.0]},
        {"NAME": "radius", "TYPE": "float", "DEFAULT": 0.09, "MIN": 0.01, "MAX": 0.5}
    ]
}*/

// Field strength of a light at p, in output heights (so it looks the same at any size).
float light(vec2 p, vec2 at) {
    vec2 d = (p - at) / RENDERSIZE.y;
    return radius * radius / (dot(d, d) + 0.0005);
}

void main() {
    vec2 p = isf_FragNormCoord * RENDERSIZE;
    float a = light(p, handA);
    float b = light(p, handB);
    float field = a + b;
    // the metaball edge: brightest where the two fields together cross 1
    float glow = smoothstep(0.6, 1.0, field) * 0.6 + 0.4 * min(field, 1.0);
    vec3 rgb = (colorA.rgb * a + colorB.rgb * b) / max(field, 1e-4) * glow;
    // a ring expanding at 0.8 output heights per second for 1.2 s
    if (burstAge < 1.2) {
        float d = distance(p, burstPos) / RENDERSIZE.y - burstAge * 0.8;
        rgb += vec3((1.0 - burstAge / 1.2) * max(0.0, 1.0 - abs(d) / 0.015));
    }
    float alpha = clamp(max(max(rgb.r, rgb.g), rgb.b), 0.0, 1.0);
    gl_FragColor = vec4(rgb / max(alpha, 1e-4), alpha);
}
