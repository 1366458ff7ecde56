"""A request the add-on cannot carry out, with the sentence that tells the
user what to do instead; operators show it in Blender's report area."""


class Refusal(Exception):
    pass


class Missing(Refusal):
    """No markers were given at all (as opposed to markers that are wrong):
    a correspondence kept on the target may serve instead."""


def sentence(text):
    """`text` as one line for Blender's report: newlines and runs of
    spaces (from a multi-line message) become single spaces."""
    return " ".join(str(text).split()) or "meshmorph stopped without saying why"
