"""Likert survey analytics and verification of published percentage tables."""
