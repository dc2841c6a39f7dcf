"""Reading and writing: scene files (both formats) and their conversion to the model."""
