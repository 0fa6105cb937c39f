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
    float d = distance(p, at) / RENDERSIZE.y;
    return radius * radius / (d * d + 0.0005);
}

void main() {
    vec2 p = isf_FragNormCoord * RENDERSIZE;
    float a = light(p, handA);
    float b = light(p, handB);
    vec3 col = colorA.rgb * a + colorB.rgb * b;
    float field = a + b;
    // the metaball edge: brightest where the two fields together cross 1
    float glow = smoothstep(0.6, 1.0, field) * 0.6 + 0.4 * clamp(field, 0.0, 1.0);
    vec3 light_col = col / max(field, 1e-4) * glow;
    // a ring expanding at 0.8 output heights per second for 1.2 s
    float ring = 0.0;
    if (burstAge < 1.2) {
        float r = burstAge * 0.8;
        float d = distance(p, burstPos) / RENDERSIZE.y;
        ring = (1.0 - burstAge / 1.2) * exp(-pow((d - r) / 0.015, 2.0));
    }
    vec3 rgb = light_col + vec3(ring);
    float alpha = clamp(max(max(rgb.r, rgb.g), rgb.b), 0.0, 1.0);
    gl_FragColor = vec4(rgb / max(alpha, 1e-4), alpha);
}
