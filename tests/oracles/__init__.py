"""Independent implementations the tests hold the product to (oracles), kept out of the
product because it no longer runs them."""
