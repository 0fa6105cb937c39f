"""`osc-in`: skeletons from OSC bridges (OSCeleton, Synapse, NI mate, KinectV2-OSC, MediaPipe) as users."""
