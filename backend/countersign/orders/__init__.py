"""Mission orders: the model, readers and writers, canonical digest, plain-language text."""
