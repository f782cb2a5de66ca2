"""Helpers shared by the bundled rules' tests."""


def tagged(model, tag):
    """The model's blocks that carry ``tag``."""
    return [b for b in model.blocks if tag in b.tags]
