"""Collects what went wrong during an export, so the engine can report it and go on."""


class Problems:
    """Warnings are for what was skipped or approximated while the render goes on; errors are for
    what stops the render (no camera, nothing to render). A script calling bpy.ops.render.render
    gets an exception for errors only."""

    def __init__(self):
        self.items = []  # (level, message); level is 'WARNING' or 'ERROR' as in Operator.report

    def warning(self, name, reason):
        self.items.append(("WARNING", "{}: {}".format(name, reason)))

    def error(self, name, reason):
        self.items.append(("ERROR", "{}: {}".format(name, reason)))

    def messages(self, level=None):
        return [message for item_level, message in self.items if level is None or item_level == level]

    def __len__(self):
        return len(self.items)
