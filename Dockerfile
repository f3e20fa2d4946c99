FROM python:3.11-slim
WORKDIR /app
COPY pyproject.toml README.md ./
COPY backend ./backend
RUN pip install --no-cache-dir .
ENV COUNTERSIGN_DATA_DIR=/data
VOLUME ["/data"]
EXPOSE 8000
CMD ["countersign", "serve", "--host", "0.0.0.0", "--port", "8000", "--data-dir", "/data"]
