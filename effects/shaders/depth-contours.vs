// depth-contours: the values that are the same for the whole frame, computed once per vertex.
flat out float invSpacing;
flat out float drift;
flat out float boost;

void main() {
    isf_vertShaderInit();
    invSpacing = 1.0 / spacing;
    drift = TIME * speed / spacing;
    boost = 1.0 + 2.0 * exp(-flash * 4.0);
}
