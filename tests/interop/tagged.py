"""A decoded value as JSON that keeps its Python type, for the interop scripts to report:
{"int": "5"}, {"float": "1.25"}, {"str": ...}, {"bytes": "DEADBEEF"}, {"bool": true}."""


def tagged(value):
    if isinstance(value, bool):
        return {"bool": value}
    if isinstance(value, int):
        return {"int": str(value)}
    if isinstance(value, float):
        return {"float": repr(value)}
    if isinstance(value, str):
        return {"str": value}
    return {"bytes": bytes(value).hex().upper()}
