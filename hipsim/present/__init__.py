"""Presentation: figures, the HTML report, the meshcat viewer and server, the human model beside the machine."""

__all__: list[str] = []
