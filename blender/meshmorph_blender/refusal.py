"""A request the add-on cannot carry out, with the sentence that tells the
user what to do instead; operators show it in Blender's report area."""


class Refusal(Exception):
    pass
