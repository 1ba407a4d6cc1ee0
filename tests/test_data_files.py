"""The files in tests/data/ come with their source and license."""

from data_files import DATA


def test_every_data_file_is_listed_with_its_source_and_license():
    readme = (DATA / "README.md").read_text()
    files = sorted(p.name for p in DATA.iterdir() if p.name != "README.md")
    assert files, "tests/data/ holds no file"
    for name in files:
        row = next((line for line in readme.splitlines() if line.startswith(f"| {name} |")), None)
        assert row is not None and "License" in row, name
        assert f"## License of {name}" in readme and "Copyright (c)" in readme, name
