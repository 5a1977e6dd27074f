"""Frames in and pictures out: video files, folders of pictures, cameras; conversions."""
