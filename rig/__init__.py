"""Virtual four-poster test rig: MuJoCo rig and car models, replay, records, analysis."""

__version__ = "0.1.0"
