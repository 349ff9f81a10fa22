"""Wakeline desktop application (PySide6 + pyqtgraph) over the core engine."""
