"""Jinja2 templates of generated code (shipped inside the wheel as symdyn.templates)."""
