"""Where the generated pages live under docs/, for the pages that link to them."""

SCHEMA_FILE = "hivex.schema.json"


def env_page(env_id: str) -> str:
    return f"environments/{env_id}.md"
