"""YAML as railvib's loader (yaml-cpp, YAML 1.2) reads it, for the scripts: 1e-05, 2.0e3 or 8.0e6 are
numbers, not the strings PyYAML's YAML 1.1 resolver makes of them (a catalogue's value written back
for --set would otherwise arrive quoted), and a time such as recorded_utc stays the text it was
written as."""
import re

import yaml


class Loader(yaml.SafeLoader):
    pass


Loader.yaml_implicit_resolvers = {
    first: [(tag, regexp) for tag, regexp in resolvers if tag != "tag:yaml.org,2002:timestamp"]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()}
Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][-+]?[0-9]+)?$"),
    list("-+0123456789."))


def load(text):
    """The YAML document in TEXT (a str or an open file) with YAML 1.2's numbers."""
    return yaml.load(text, Loader=Loader)
