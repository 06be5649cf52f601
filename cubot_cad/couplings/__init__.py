"""The couplings between robots: connector parts (front-rear, side rail, top twist), their compliance, the twist key and latch drives.
May import the core and cubot_cad.hardware.
"""
