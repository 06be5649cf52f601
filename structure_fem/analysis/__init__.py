"""Studies on the model: thresholds per structure, margins, the design search, calibration, the pier rule.
May import the core, couplings and model.
"""
