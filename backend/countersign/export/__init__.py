"""Vehicle formats written from orders (IMC, MOOS-IvP) and approved packages (DESIGN.md layout).

Imports `orders` and `verify` only; the store, the web app and the command line call in."""
