"""`mediapipe`: users, hands and gestures from colour frames (the `webcam` source) with MediaPipe."""
