"""A model's texts in several languages: ``description = { fr = "masse de (S)", en = "mass of (S)" }``.

Model files come with their words (the title, the descriptions of the model, its parameters,
coordinates and constraints) for the report, which is written in French or in English.  A plain
string stays valid: it is used in every language.  A table gives one text per language; it is
read into a `Text`, a ``str`` that reads as its English (else its first) text everywhere a
string is expected (JSON, the terminal), and gives the others by `in_language`.
"""

from __future__ import annotations

from collections.abc import Mapping

__all__ = ["LANGUAGES", "Text", "in_language"]

#: The languages a model's texts may be written in (those of the report).
LANGUAGES = ("fr", "en")


class Text(str):
    """A text in one or more of `LANGUAGES`; as a ``str``, its English text (else the first given)."""

    translations: Mapping[str, str]

    def __new__(cls, translations: Mapping[str, str]) -> Text:
        if not translations:
            raise ValueError("a Text needs at least one language")
        default = translations.get("en", next(iter(translations.values())))
        obj = super().__new__(cls, default)
        obj.translations = dict(translations)
        return obj

    def __getnewargs__(self) -> tuple[dict[str, str]]:  # type: ignore[override]  # pickling: rebuild from the table
        return (dict(self.translations),)

    def in_language(self, lang: str) -> str:
        """The text in ``lang``, else the default one."""
        return self.translations.get(lang, str(self))


def in_language(text: str | None, lang: str) -> str | None:
    """``text`` in ``lang`` when it is a `Text` with that language, else ``text`` itself (a plain string).

    Parameters
    ----------
    text : str or None
        A plain string, or a `Text` that holds one per language.
    lang : str
        The language, ``"en"`` or ``"fr"``.

    Returns
    -------
    str or None
        ``text`` in ``lang`` when it is a `Text` with that language, else ``text`` itself.
    """
    return text.in_language(lang) if isinstance(text, Text) else text
