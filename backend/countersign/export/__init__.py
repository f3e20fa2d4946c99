"""Vehicle formats written from orders (IMC, MOOS-IvP) and the vehicle files of approved packages.

Imports `orders` and `verify` only; the store, the web app and the command line call in."""
